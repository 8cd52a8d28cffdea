using System;
using System.Collections.Generic;
using System.Threading;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Core.Quality
{
    /// <summary>Leak repair of a seed (Documentation~/leaks.md "A leak-aware default", 1): each round adds, in every
    /// tetrahedron some leaking point lies in (outside the hull: the tetrahedron owning its hull triangle), the leaking point
    /// of largest error (ties, errors within <see cref="InsertionRanking.Tie"/> of the largest: the lower index). A probe at a leaking point ends that point's leak and splits its
    /// tetrahedron where it leaked worst; batched refinement only removes probes, so a leak of its seed could not be undone
    /// later. With pinned probes (Documentation~/pins.md) no probe is added within a pin's keep distance: a leaking point
    /// there is left to the pinned probe, and its tetrahedron gets the worst leaking point that may become a probe, if any.
    /// Port of lpnn/quality/placement/leak_aware.py leak_repaired.</summary>
    internal static class LeakRepair
    {
        /// <summary>Repair rounds on the seed (lpnn/quality/placement/leak_aware.py REPAIR_ROUNDS; benchmarks.md "Light leaks" measured 1 and 3).</summary>
        public const int DefaultRounds = 2;

        /// <summary><paramref name="probes"/> (evaluation point indices) plus, in each of up to <paramref name="rounds"/>
        /// rounds, the worst leaking point of every leaking tetrahedron; stops early when no point that may become a probe
        /// leaks. <paramref name="blocked"/> (null: none; one flag per point, e.g. <see cref="Pins.Blocked"/>): points that
        /// never become a probe, passed over when leaking. <paramref name="memo"/> (null: none): segments remembered across the
        /// rounds and shared with the refinement that follows (<see cref="LeakWeighting.MemoFor"/>). Sorted.</summary>
        public static int[] Repaired(ReferenceLighting reference, ITetrahedralizer tetrahedralizer, int[] probes, IRaycaster raycaster,
            int rounds = DefaultRounds, CancellationToken cancel = default, bool[] blocked = null, SegmentMemo memo = null)
        {
            if (reference == null) throw new ArgumentNullException(nameof(reference));
            if (tetrahedralizer == null) throw new ArgumentNullException(nameof(tetrahedralizer));
            if (raycaster == null) throw new ArgumentNullException(nameof(raycaster));
            if (rounds < 0) throw new PlacementErrorException("leak repair rounds " + rounds + " must be >= 0");
            if (blocked != null && blocked.Length != reference.Count)
                throw new PlacementErrorException("blocked must flag each of the " + InvariantFormat.Count(reference.Count) + " points, got " +
                                                  InvariantFormat.Count(blocked.Length));
            ProbeIndices.Check(probes, reference.Count);
            var current = (int[])probes.Clone();
            Array.Sort(current);
            for (int round = 0; round < rounds; round++)
            {
                cancel.ThrowIfCancellationRequested();
                int[] added = WorstLeakPerCell(reference, tetrahedralizer, current, raycaster, blocked, memo);
                if (added.Length == 0) break;
                var union = new SortedSet<int>(current);
                union.UnionWith(added);
                current = new int[union.Count];
                union.CopyTo(current);
            }
            return current;
        }

        /// <summary>Per cell holding a leaking point that is not <paramref name="blocked"/>, the one of largest error (ties: the lower index).</summary>
        private static int[] WorstLeakPerCell(ReferenceLighting reference, ITetrahedralizer tetrahedralizer, int[] probes, IRaycaster raycaster, bool[] blocked,
            SegmentMemo memo)
        {
            int[] tetrahedra = TetrahedronNumbering.Tetrahedralize(tetrahedralizer, reference, probes);
            var visited = new StencilLog();
            var errorOf = new double[reference.Count];
            PlacementError.InterpolateOthers(reference, probes, tetrahedra,
                (int p, ref Stencil stencil, double[] interpolated) =>
                    errorOf[p] = PointErrorMetrics.Irradiance(interpolated, reference.Light, p * ReferenceLighting.LightValues, reference.SceneScale),
                visited.Visitor);
            IReadOnlyList<int> points = visited.Points;
            IReadOnlyList<Stencil> stencils = visited.Stencils;
            var errors = new double[points.Count];
            for (int i = 0; i < errors.Length; i++) errors[i] = errorOf[points[i]];
            bool[] leaking = LeakCheck.Leaking(reference, probes, points, stencils, raycaster, memo);
            // Per cell the lowest index whose error is within InsertionRanking.Tie of the cell's largest among its leaking
            // points (points ascend): errors where the light is even are round-off (~1e-15) whose last bits hang on the
            // arithmetic's order, so an exact comparison let rounding pick the probe, and Python picked another (oa_koth1,
            // Documentation~/quality.md §5.1).
            var cells = new int[points.Count];
            int cellCount = 0;
            for (int i = 0; i < points.Count; i++)
            {
                cells[i] = leaking[i] && (blocked == null || !blocked[points[i]]) ? stencils[i].Cell : -1;
                cellCount = Math.Max(cellCount, cells[i] + 1);
            }
            var added = new List<int>();
            foreach (int i in InsertionRanking.FirstPerCell(cells, errors, cellCount))
                if (i >= 0) added.Add(points[i]);
            added.Sort();
            return added.ToArray();
        }
    }
}
