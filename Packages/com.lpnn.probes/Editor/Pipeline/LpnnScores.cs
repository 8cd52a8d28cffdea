using System;
using System.Collections.Generic;
using System.IO;
using Lpnn.Probes.Core.IO;
using Lpnn.Probes.Core.Scoring;
using UnityEditor;
using UnityEditor.SceneManagement;
using UnityEngine;
using UnityEngine.SceneManagement;

namespace Lpnn.Probes.Editor
{
    /// <summary>A volume's last scores, outside the volume (issue 31; Core.Scoring.ScoreStore says why): the editor session
    /// holds the record, and a copy goes to <c>Library/LpnnProbes/Scores</c> keyed by the volume's GlobalObjectId
    /// (UnityCsReference Editor/Mono/GlobalObjectId.bindings.cs GetGlobalObjectIdSlow(Object), ToString), so the preview,
    /// the gizmos and the Network method's Apply survive script reloads and editor restarts as they did when the record was
    /// a serialized field — while scenes, prefab overrides and player builds hold none of it. A volume in a scene never
    /// saved (or in a preview scene) has no stable id: its scores stay in the session, and are written when its scene is
    /// saved (EditorSceneManager.sceneSaved, Editor/Mono/SceneManagement/EditorSceneManager.cs). Compiled against the API
    /// surfaces only; it has not run in a Unity editor.</summary>
    internal static class LpnnScores
    {
        static LpnnScores()
        {
            EditorSceneManager.sceneSaved += WriteUnwritten;
        }

        /// <summary>The volume's record: the session's, else the one stored in the Library (read once per session), else a new
        /// empty one. Cheap after the first call (gizmos and the inspector ask on every repaint).</summary>
        public static ScoreRecord For(LpnnVolume volume)
        {
            var session = LpnnSession.For(volume);
            if (session.Scores != null) return session.Scores;
            session.Scores = Read(volume) ?? new ScoreRecord();
            return session.Scores;
        }

        /// <summary>Keeps <paramref name="record"/> as the volume's scores (the Scoring step's result) and writes it to the
        /// Library when the volume has a stable id; otherwise when its scene is first saved.</summary>
        public static void Store(LpnnVolume volume, ScoreRecord record)
        {
            if (record == null) throw new ArgumentNullException(nameof(record));
            var session = LpnnSession.For(volume);
            session.Scores = record;
            session.ScoresUnwritten = !Write(volume, record);
        }

        /// <summary>Deletes the volume's Library copy (its session keeps what it holds); for tests that save scenes.</summary>
        internal static void DeleteStoredCopy(LpnnVolume volume)
        {
            string path = PathOf(volume, out _);
            if (path != null && File.Exists(path)) File.Delete(path);
        }

        /// <summary>The file of the volume's record, or null when the volume has no stable id (<paramref name="key"/>: its id).</summary>
        private static string PathOf(LpnnVolume volume, out string key)
        {
            key = GlobalObjectId.GetGlobalObjectIdSlow(volume).ToString();
            if (!ScoreStore.IsPersistentKey(key)) return null;
            return Path.Combine(LpnnPaths.ProjectRoot, ScoreStore.Folder, ScoreStore.FileName(key));
        }

        private static ScoreRecord Read(LpnnVolume volume)
        {
            string path = PathOf(volume, out string key);
            if (path == null || !File.Exists(path)) return null;
            try
            {
                return ScoreRecordFile.Decode(File.ReadAllBytes(path), key, "of volume '" + volume.name + "' (" + path + ")");
            }
            catch (Exception e) when (e is IOException || e is UnauthorizedAccessException || e is ScoringException)
            {
                // A cache: a damaged copy costs a Scoring run, never an error dialog.
                Debug.LogWarning("[LPNN] " + e.Message + "; run the Scoring step again", volume);
                return null;
            }
        }

        /// <returns>True when written (or nothing needed writing), false when the volume has no stable id yet.</returns>
        private static bool Write(LpnnVolume volume, ScoreRecord record)
        {
            string path = PathOf(volume, out string key);
            if (path == null) return false;
            try
            {
                string folder = Path.GetDirectoryName(path);
                Directory.CreateDirectory(folder);
                byte[] bytes = ScoreRecordFile.Encode(record, key);
                AtomicFile.Write(path, stream => stream.Write(bytes, 0, bytes.Length));
                Prune(folder);
            }
            catch (Exception e) when (e is IOException || e is UnauthorizedAccessException)
            {
                Debug.LogWarning("[LPNN] the scores of volume '" + volume.name + "' could not be kept in " + path + " (" + e.Message +
                                 "); they last until the next script reload", volume);
            }
            return true;
        }

        /// <summary>Keeps the Library folder bounded (Core.Scoring.ScoreStore.ToPrune: the most recently written records).</summary>
        private static void Prune(string folder)
        {
            var files = new List<ScoreStore.StoredFile>();
            foreach (string path in Directory.GetFiles(folder, "*" + ScoreStore.Extension))
            {
                var info = new FileInfo(path);
                files.Add(new ScoreStore.StoredFile { Name = path, WrittenUtc = info.LastWriteTimeUtc, Bytes = info.Length });
            }
            foreach (string path in ScoreStore.ToPrune(files)) File.Delete(path);
        }

        /// <summary>A scene just saved gives its volumes stable ids — a first save, or a Save As under a new scene GUID: write the
        /// scores of its volumes that have no copy under their current id (volumes of scenes still unsaved keep waiting).</summary>
        private static void WriteUnwritten(Scene scene)
        {
            foreach (var entry in LpnnSession.WithScores())
            {
                var volume = entry.Key;
                var session = entry.Value;
                if (volume.gameObject.scene.path != scene.path) continue;
                string path = PathOf(volume, out _);
                if (session.ScoresUnwritten || (path != null && !File.Exists(path)))
                    session.ScoresUnwritten = !Write(volume, session.Scores);
            }
        }
    }

    /// <summary>The data a volume serialized by 0.1.0 left behind (issue 31: the record was the field <c>lastScores</c>).
    /// On a scene object or prefab asset Unity skips fields no script declares when it loads and leaves them out at the
    /// next save, and a player build serializes the loaded object, so old data never ships. On a prefab instance the
    /// scores were stored as property modifications, and those Unity keeps as "unused overrides" in the scene until they
    /// are removed (UnityCsReference Editor/Mono/Prefabs/PrefabUtility.cs RemovePrefabInstanceUnusedOverrides, which does
    /// it with SetPropertyModifications and an Undo record, PrefabUtility.bindings.cs). The inspector offers to remove only
    /// ours (Core.Scoring.ScoreStore.IsLegacyScorePath), leaving the instance's other overrides as they are.</summary>
    internal static class LegacyScoreOverrides
    {
        /// <summary>The outermost prefab instance root holding the volume's modifications, or null (not a prefab instance).</summary>
        private static GameObject RootOf(LpnnVolume volume) =>
            PrefabUtility.IsPartOfPrefabInstance(volume) ? PrefabUtility.GetOutermostPrefabInstanceRoot(volume) : null;

        /// <summary>How many of the volume's prefab instance modifications are of the retired record (0: none, or not an instance).</summary>
        public static int Count(LpnnVolume volume)
        {
            var root = RootOf(volume);
            if (root == null) return 0;
            int count = 0;
            foreach (var modification in PrefabUtility.GetPropertyModifications(root) ?? new PropertyModification[0])
                if (IsOurs(modification)) count++;
            return count;
        }

        /// <summary>Removes them (one Undo step); returns how many.</summary>
        public static int Remove(LpnnVolume volume)
        {
            var root = RootOf(volume);
            if (root == null) return 0;
            var modifications = PrefabUtility.GetPropertyModifications(root) ?? new PropertyModification[0];
            var kept = new List<PropertyModification>(modifications.Length);
            foreach (var modification in modifications)
                if (!IsOurs(modification)) kept.Add(modification);
            int removed = modifications.Length - kept.Count;
            if (removed == 0) return 0;
            Undo.RegisterCompleteObjectUndo(root, "Remove old LPNN score overrides");
            PrefabUtility.SetPropertyModifications(root, kept.ToArray());
            return removed;
        }

        private static bool IsOurs(PropertyModification modification) =>
            modification != null && modification.target is LpnnVolume && ScoreStore.IsLegacyScorePath(modification.propertyPath);
    }
}
