using System;
using System.Collections.Generic;
using System.Threading;
using Lpnn.Probes.Core;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Quality;
using UnityEngine;
using NumericsVector3 = System.Numerics.Vector3;

namespace Lpnn.Probes.Editor
{
    /// <summary>Light leaking through walls at the points in use (Documentation~/leaks.md "What is reported"): the
    /// inspector's "N of M points in use leak" line beside the error, and the leaking tetrahedra the Scene view draws
    /// (<see cref="LpnnGizmos"/>). The tetrahedra are Unity's (<see cref="UnityTetrahedralizer"/>, as the error's); the rays
    /// are the scene's physics (<see cref="PhysicsRaycaster"/> inside a <see cref="RaycastScope"/>, as the Features step and
    /// <see cref="VolumeInUse"/> cast them). Kept per volume for one lighting and one probe set.</summary>
    internal static class LeaksAtPointsInUse
    {
        /// <summary>The Scene view draws at most this many leaking tetrahedra (6 lines each), and says so when there are more.</summary>
        public const int MaxDrawnTetrahedra = 2000;

        /// <summary>One volume's report: the probe set and lighting it was made for, the text, and the edges to draw.</summary>
        internal sealed class Entry
        {
            public int[] Probes;
            public float[] Sh;
            public LeakReport Report;
            /// <summary>The inspector line (or why the report is unavailable).</summary>
            public string Text;
            public bool Failed;
            /// <summary>World corners of the drawn tetrahedra, 4 per tetrahedron, at most <see cref="MaxDrawnTetrahedra"/>.</summary>
            public Vector3[] Corners = new Vector3[0];
        }

        private static readonly Dictionary<ObjectKey, Entry> Entries = new Dictionary<ObjectKey, Entry>();

        /// <summary>The report of this probe set (evaluation point indices of the session's grid) under the session's lighting,
        /// or null when it was not computed (never computes).</summary>
        public static Entry Known(LpnnVolume volume, LpnnSession session, int[] probes)
        {
            if (volume == null || probes == null) return null;
            if (!Entries.TryGetValue(ObjectKey.Of(volume), out var entry)) return null;
            return entry.Sh == session.Sh && SameProbes(entry.Probes, probes) ? entry : null;
        }

        /// <summary>The last report of the volume whatever its probes (the Scene view draws it until the next one), or null.</summary>
        public static Entry Last(LpnnVolume volume) =>
            volume != null && Entries.TryGetValue(ObjectKey.Of(volume), out var entry) ? entry : null;

        /// <summary>Forgets the volume's report (its probes were cleared).</summary>
        public static void Forget(LpnnVolume volume)
        {
            if (volume != null) Entries.Remove(ObjectKey.Of(volume));
        }

        /// <summary>Computes the report under a cancellable progress bar (<see cref="EditorProgressScope"/>) and keeps it; a
        /// cancel keeps the previous one, a failure keeps its reason as the text.</summary>
        public static Entry Run(LpnnVolume volume, LpnnSession session, EvaluationGrid grid, int[] probes)
        {
            var entry = new Entry { Probes = (int[])probes.Clone(), Sh = session.Sh };
            try
            {
                using (var progress = new EditorProgressScope("LPNN Probes: leaks"))
                    entry.Report = Compute(volume, session, grid, probes, progress.Callback, progress.Token);
                entry.Text = Describe(entry.Report, session.InUse);
                entry.Corners = Corners(entry.Report, PlacementInputs.Reference(session, grid), probes);
            }
            catch (OperationCanceledException)
            {
                return Known(volume, session, probes);
            }
            catch (LpnnException e)
            {
                entry.Text = "Leaks unavailable: " + e.Message;
                entry.Failed = true;
            }
            catch (Exception e)
            {
                // The placement stays; the line says what happened and the console has the details (Debug.LogException:
                // UnityCsReference Runtime/Export/Debug/Debug.bindings.cs).
                entry.Text = "Leaks unavailable: unexpected error (" + e.GetType().Name + ": " + e.Message + "); the console has the details.";
                entry.Failed = true;
                Debug.LogException(e, volume);
            }
            Entries[ObjectKey.Of(volume)] = entry;
            return entry;
        }

        /// <summary>The leak report of <paramref name="probes"/>: Unity's tetrahedralisation of them, and physics segment rays
        /// from each point in use (the session's report mask for All; every point of the grid for Band and Reachable, which
        /// holds the points in use only) to the probes of its stencil.</summary>
        public static LeakReport Compute(LpnnVolume volume, LpnnSession session, EvaluationGrid grid, int[] probes, ProgressCallback progress,
            CancellationToken cancel)
        {
            var reference = PlacementInputs.Reference(session, grid);
            var positions = new NumericsVector3[probes.Length];
            for (int k = 0; k < probes.Length; k++) positions[k] = reference.GetPosition(probes[k]);
            // The same tetrahedralisation the estimated error uses (PlacementInputs.Evaluator): UnityEditor.Lightmapping.Tetrahedralize,
            // UnityCsReference Editor/Mono/GI/Lightmapping.bindings.cs.
            int[] tetrahedra = new UnityTetrahedralizer().Tetrahedralize(positions);
            bool[] mask = session.InUse == null ? null : session.InUse.GridMask;
            using (new RaycastScope(volume, volume.AddTemporaryColliders))
            {
                // RaycastCommand batches in the volume's physics scene (Prefab Mode too): UnityCsReference
                // Modules/Physics/ScriptBindings/QueryCommand.bindings.cs; Component.gameObject / GameObject.scene:
                // Runtime/Export/Scripting/Component.bindings.cs, Runtime/Export/Scripting/GameObject.bindings.cs.
                var rays = new PhysicsRaycaster(volume.gameObject.scene);
                return LeakReport.Compute(reference, probes, tetrahedra, mask, rays, progress, cancel);
            }
        }

        /// <summary>"Leaks: 12 of 3,456 points in use leak (0.35 %), in 9 tetrahedra (drawn in the Scene view)."; for All
        /// without a report mask the share is over every point, and says so.</summary>
        public static string Describe(LeakReport report, InUsePoints inUse)
        {
            string text = report.Sentence(CountedNote(inUse));
            if (report.TetrahedronCount > 0)
                text += report.TetrahedronCount > MaxDrawnTetrahedra
                    ? " (the Scene view draws the first " + InvariantFormat.Count(MaxDrawnTetrahedra) + ")"
                    : " (drawn in the Scene view)";
            return text + ".";
        }

        /// <summary>" (every point counted: …)" when the rule is All and its report mask is unknown, so the share is over every
        /// point rather than the points in use; "" otherwise.</summary>
        public static string CountedNote(InUsePoints inUse) =>
            inUse != null && !inUse.Filters && !inUse.Known ? " (every point counted: " + inUse.Unavailable + ")" : "";

        private static Vector3[] Corners(LeakReport report, ReferenceLighting reference, int[] probes)
        {
            int drawn = Math.Min(report.TetrahedronCount, MaxDrawnTetrahedra);
            var corners = new Vector3[4 * drawn];
            for (int i = 0; i < corners.Length; i++) corners[i] = reference.GetPosition(probes[report.LeakingTetrahedra[i]]).ToUnity();
            return corners;
        }

        private static bool SameProbes(int[] a, int[] b)
        {
            if (ReferenceEquals(a, b)) return true;
            if (a.Length != b.Length) return false;
            for (int i = 0; i < a.Length; i++) if (a[i] != b[i]) return false;
            return true;
        }
    }
}
