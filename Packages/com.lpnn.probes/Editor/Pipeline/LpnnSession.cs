using System;
using System.Collections.Generic;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Scoring;
using UnityEditor;
using UnityEditor.SceneManagement;

namespace Lpnn.Probes.Editor
{
    /// <summary>The transient results of one volume in this editor session: the grid, the lighting at its points, the
    /// features, the scores and the model runner — data only (what the inspector shows about each step is in StepStates).
    /// Never serialized: a domain reload drops them (the scores are also kept in the project's Library folder, LpnnScores,
    /// so they come back). Results are replaced only when a step succeeds, so a cancelled or failed step leaves the
    /// previous state intact.</summary>
    public sealed class LpnnSession : IDisposable
    {
        private static readonly Dictionary<ObjectKey, LpnnSession> Sessions = new Dictionary<ObjectKey, LpnnSession>();

        static LpnnSession()
        {
            // The Sentis worker holds native/GPU memory: release it before scripts reload
            // (AssemblyReloadEvents: UnityCsReference Editor/Mono/AssemblyReloadEvents.cs).
            AssemblyReloadEvents.beforeAssemblyReload += DisposeAll;
            // A closed scene or a deleted volume must not keep its grid, lighting, features, cached insertion orders (keyed by
            // the session's SH) and worker until the next domain reload (~336 MB per 10⁶ points; issue 31). Both events
            // come after the objects are destroyed, when Unity's == null is true for them (UnityCsReference
            // Editor/Mono/SceneManagement/EditorSceneManager.cs sceneClosed, Editor/Mono/EditorApplication.cs hierarchyChanged,
            // Runtime/Export/Scripting/UnityEngineObject.bindings.cs operator ==).
            EditorSceneManager.sceneClosed += scene => ReleaseOrphans();
            EditorApplication.hierarchyChanged += ReleaseOrphans;
        }

        /// <summary>The volume this session belongs to (destroyed: == null), to release the session with it.</summary>
        private LpnnVolume _volume;

        public EvaluationGrid Grid { get; private set; }
        /// <summary>The volume signature the grid was built for (GridSignature.Of).</summary>
        public string GridSignature { get; private set; } = "";
        /// <summary>27 floats per grid point (Documentation~/sh.md).</summary>
        public float[] Sh { get; private set; }
        public string LightingDescription { get; private set; } = "";
        public FeatureSet Features { get; private set; }
        /// <summary>What the in-use rule decided when the grid was built (null for a grid set without it).</summary>
        internal InUsePoints InUse { get; private set; }

        /// <summary>The stored scores already matched against <see cref="Grid"/> (so the inspector's live preview does not
        /// compare every id on every repaint).</summary>
        internal float[] ScoresVerifiedForGrid { get; set; }

        /// <summary>The volume's last scores (LpnnScores.For reads them, from the Library after a reload); null until asked.</summary>
        internal ScoreRecord Scores { get; set; }

        /// <summary>The scores wait for the volume's scene to be saved before they can be written to the Library.</summary>
        internal bool ScoresUnwritten { get; set; }

        /// <summary>The cached model runner (a Sentis worker), owned by this session.</summary>
        public IDisposable ModelRunner { get; set; }

        public static LpnnSession For(LpnnVolume volume)
        {
            var key = ObjectKey.Of(volume);
            if (!Sessions.TryGetValue(key, out var session))
            {
                session = new LpnnSession { _volume = volume };
                Sessions[key] = session;
            }
            return session;
        }

        public static void Forget(LpnnVolume volume)
        {
            var key = ObjectKey.Of(volume);
            if (!Sessions.TryGetValue(key, out var session)) return;
            session.Dispose();
            Sessions.Remove(key);
        }

        public void SetGrid(EvaluationGrid grid, string signature) => SetGrid(grid, signature, null);

        /// <summary>A new grid with the in-use rule's outcome (Band and Reachable: <paramref name="grid"/> holds the in-use points
        /// of <see cref="InUsePoints.AllPoints"/>).</summary>
        internal void SetGrid(EvaluationGrid grid, string signature, InUsePoints inUse)
        {
            Grid = grid;
            InUse = inUse;
            GridSignature = signature ?? "";
            ScoresVerifiedForGrid = null;
            Sh = null;
            LightingDescription = "";
            Features = null;
        }

        public void SetLighting(float[] sh, string description)
        {
            Sh = sh;
            LightingDescription = description ?? "";
            Features = null;
        }

        public void SetFeatures(FeatureSet features) => Features = features;

        public void Dispose()
        {
            ModelRunner?.Dispose();
            ModelRunner = null;
        }

        /// <summary>Disposes and drops the sessions whose volume was destroyed (its scene closed, or the component deleted).</summary>
        internal static void ReleaseOrphans()
        {
            List<ObjectKey> orphans = null;
            foreach (var entry in Sessions)
                if (entry.Value._volume == null) (orphans ?? (orphans = new List<ObjectKey>())).Add(entry.Key);
            if (orphans == null) return;
            foreach (var key in orphans)
            {
                Sessions[key].Dispose();
                Sessions.Remove(key);
            }
        }

        /// <summary>The live volumes whose session holds scores (LpnnScores writes them when their scene is saved).</summary>
        internal static List<KeyValuePair<LpnnVolume, LpnnSession>> WithScores()
        {
            var holding = new List<KeyValuePair<LpnnVolume, LpnnSession>>();
            foreach (var session in Sessions.Values)
                if (session.Scores != null && !session.Scores.IsEmpty && session._volume != null)
                    holding.Add(new KeyValuePair<LpnnVolume, LpnnSession>(session._volume, session));
            return holding;
        }

        /// <summary>How many volumes have a session (for tests of the release).</summary>
        internal static int Count => Sessions.Count;

        private static void DisposeAll()
        {
            foreach (var session in Sessions.Values) session.Dispose();
            Sessions.Clear();
        }
    }
}
