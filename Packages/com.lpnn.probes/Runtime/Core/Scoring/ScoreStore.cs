using System;
using System.Collections.Generic;
using System.Globalization;
using System.Security.Cryptography;
using System.Text;

namespace Lpnn.Probes.Core.Scoring
{
    /// <summary>Where a volume's scores live between steps, sessions and editor restarts — the decisions, engine-free (the
    /// editor's LpnnScores does the Unity side). Not in the scene: a serialized field put ~5 values per point into every
    /// scene and prefab override and into player builds (issue 31). Not an asset next to the scene: scores are a cache
    /// derived from the scene (the Scoring step rebuilds them in seconds from the Features step), an asset would show in the
    /// project, travel through version control and need renaming with its scene. So: the editor session holds the record,
    /// and a copy goes to the project's Library folder (Unity's own cache folder: per machine, never versioned, never in a
    /// build), keyed by the volume's GlobalObjectId, so the preview and Apply of the Network method survive script reloads
    /// and editor restarts as before.</summary>
    internal static class ScoreStore
    {
        /// <summary>Project-relative folder of the stored records.</summary>
        public const string Folder = "Library/LpnnProbes/Scores";
        public const string Extension = ".lpnnscores";
        /// <summary>At most this many records are kept (the most recently written); ~17 bytes per point each.</summary>
        public const int MaxFiles = 64;
        public const long MaxBytes = 512L * 1024 * 1024;
        /// <summary>The field LpnnVolume serialized the record in up to 0.1.0 (the data Unity now ignores on load).</summary>
        public const string LegacyField = "lastScores";

        /// <summary>The file name of a volume's record: a hash of its key (GlobalObjectId strings hold characters and lengths
        /// no file system should have to take).</summary>
        public static string FileName(string key)
        {
            if (string.IsNullOrEmpty(key)) throw new ArgumentException("no key", nameof(key));
            using (var sha = SHA256.Create())
            {
                byte[] hash = sha.ComputeHash(Encoding.UTF8.GetBytes(key));
                var name = new StringBuilder(32 + Extension.Length);
                for (int i = 0; i < 16; i++) name.Append(hash[i].ToString("x2", CultureInfo.InvariantCulture));
                return name.Append(Extension).ToString();
            }
        }

        /// <summary>Whether a GlobalObjectId string (UnityCsReference Editor/Mono/GlobalObjectId.bindings.cs ToString:
        /// "GlobalObjectId_V1-{identifierType}-{assetGUID}-{targetObjectId}-{targetPrefabId}") names the volume stably across
        /// sessions: not the null identifier (type 0: an unsaved scene, a preview scene), with an asset GUID and an object id.
        /// Other volumes keep their scores in the session only (until the next script reload).</summary>
        public static bool IsPersistentKey(string globalObjectId)
        {
            if (string.IsNullOrEmpty(globalObjectId)) return false;
            string[] parts = globalObjectId.Split('-');
            if (parts.Length != 5 || parts[0] != "GlobalObjectId_V1") return false;
            if (!int.TryParse(parts[1], NumberStyles.None, CultureInfo.InvariantCulture, out int type) || type == 0) return false;
            if (parts[2].Length != 32 || parts[2].Trim('0').Length == 0) return false;
            foreach (char c in parts[2])
                if (!Uri.IsHexDigit(c)) return false;
            return ulong.TryParse(parts[3], NumberStyles.None, CultureInfo.InvariantCulture, out ulong target) && target != 0 &&
                   ulong.TryParse(parts[4], NumberStyles.None, CultureInfo.InvariantCulture, out _);
        }

        /// <summary>A stored file as the prune sees it.</summary>
        public struct StoredFile
        {
            public string Name;
            public DateTime WrittenUtc;
            public long Bytes;
        }

        /// <summary>The files to delete so that at most <paramref name="maxFiles"/> files and <paramref name="maxBytes"/> bytes remain,
        /// the most recently written kept first; the newest file is always kept (it was just written).</summary>
        public static List<string> ToPrune(IReadOnlyList<StoredFile> files, int maxFiles = MaxFiles, long maxBytes = MaxBytes)
        {
            if (files == null) throw new ArgumentNullException(nameof(files));
            var ordered = new List<StoredFile>(files);
            ordered.Sort((a, b) =>
            {
                int byTime = b.WrittenUtc.CompareTo(a.WrittenUtc);
                return byTime != 0 ? byTime : string.CompareOrdinal(a.Name, b.Name);
            });
            var prune = new List<string>();
            long kept = 0;
            for (int f = 0; f < ordered.Count; f++)
            {
                bool keep = f == 0 || (f < maxFiles && kept + ordered[f].Bytes <= maxBytes);
                if (keep) kept += ordered[f].Bytes;
                else prune.Add(ordered[f].Name);
            }
            return prune;
        }

        /// <summary>Whether a prefab instance's property modification is of the retired serialized record ("lastScores" or a
        /// path below it): Unity keeps such modifications as unused overrides after the field is gone
        /// (UnityCsReference Editor/Mono/Prefabs/PrefabUtility.cs RemovePrefabInstanceUnusedOverrides), so they would stay in
        /// the scene until removed.</summary>
        public static bool IsLegacyScorePath(string propertyPath) =>
            propertyPath != null && (propertyPath == LegacyField || propertyPath.StartsWith(LegacyField + ".", StringComparison.Ordinal));
    }
}
