using System;
using System.Collections.Generic;
using System.Numerics;
using System.Threading;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.InUse;
using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Core.Quality
{
    /// <summary>Light leaking through walls (Documentation~/leaks.md): an evaluation point leaks when a probe of weight
    /// above <see cref="MinimumWeight"/> in its stencil is not visible from it, so its lighting blends the other side of a
    /// wall. Python's lpnn.quality.metric.leaks decides exactly alike (Tests/Data/leaks_golden.json).</summary>
    internal static class LeakCheck
    {
        /// <summary>Stencil weights at or below this are round-off (a point on a shared face gets weights within 1e-9 of
        /// zero), not light.</summary>
        public const double MinimumWeight = 1e-6;

        /// <summary>Points per batch of segment casts: at most 4 segments each, so the buffers stay a few MB at 10^6 points.</summary>
        private const int PointsPerBatch = 65536;

        /// <summary>Which evaluation points of <paramref name="reference"/> leak under the placement (<paramref name="probes"/>:
        /// evaluation point indices; <paramref name="tetrahedra"/>: 4 indices into them per tetrahedron, as Unity's
        /// tetrahedralisation returns them). Probes never leak.</summary>
        public static bool[] Find(ReferenceLighting reference, int[] probes, int[] tetrahedra, IRaycaster raycaster)
        {
            if (reference == null) throw new ArgumentNullException(nameof(reference));
            var visited = new StencilLog();
            PlacementError.InterpolateOthers(reference, probes, tetrahedra, null, visited.Visitor);
            var leaks = Leaking(reference, probes, visited.Points, visited.Stencils, raycaster);
            var leaking = new bool[reference.Count];
            for (int i = 0; i < visited.Count; i++) leaking[visited.Points[i]] = leaks[i];
            return leaking;
        }

        /// <summary>Whether each of <paramref name="points"/> (evaluation point indices) leaks through its stencil
        /// (<paramref name="stencils"/>, same order, probe-list indices into <paramref name="probes"/>), in batches of
        /// <see cref="PointsPerBatch"/>; one entry per point given. Shared by <see cref="Find"/> and the leak weighting of
        /// batched refinement, so both decide alike.</summary>
        internal static bool[] Leaking(ReferenceLighting reference, int[] probes, IReadOnlyList<int> points, IReadOnlyList<Stencil> stencils,
            IRaycaster raycaster) => Leaking(reference, probes, points, stencils, raycaster, null, CancellationToken.None);

        /// <summary>As above, reporting the rays' progress and honouring <paramref name="cancel"/> (the inspector's leak report).</summary>
        internal static bool[] Leaking(ReferenceLighting reference, int[] probes, IReadOnlyList<int> points, IReadOnlyList<Stencil> stencils,
            IRaycaster raycaster, ProgressCallback progress, CancellationToken cancel)
        {
            if (points.Count != stencils.Count)
                throw new ArgumentException("points (" + points.Count + ") and stencils (" + stencils.Count + ") differ in length");
            var probePositions = new Vector3[probes.Length];
            for (int k = 0; k < probes.Length; k++) probePositions[k] = reference.GetPosition(probes[k]);
            var leaking = new bool[points.Count];
            for (int start = 0; start < points.Count; start += PointsPerBatch)
            {
                int count = Math.Min(PointsPerBatch, points.Count - start);
                var positions = new Vector3[count];
                var batch = new Stencil[count];
                for (int b = 0; b < count; b++)
                {
                    positions[b] = reference.GetPosition(points[start + b]);
                    batch[b] = stencils[start + b];
                }
                var leaks = StencilLeaks(positions, probePositions, batch, raycaster, progress, cancel);
                Array.Copy(leaks, 0, leaking, start, count);
            }
            return leaking;
        }

        /// <summary>As <see cref="Leaking(ReferenceLighting, int[], IReadOnlyList{int}, IReadOnlyList{Stencil}, IRaycaster)"/>, the
        /// segments looked up in <paramref name="memo"/> first (null: none) and those cast remembered there: the same answers,
        /// each segment cast about once over a placement (<see cref="SegmentMemo"/>).</summary>
        internal static bool[] Leaking(ReferenceLighting reference, int[] probes, IReadOnlyList<int> points, IReadOnlyList<Stencil> stencils,
            IRaycaster raycaster, SegmentMemo memo)
        {
            if (memo == null) return Leaking(reference, probes, points, stencils, raycaster);
            if (reference == null) throw new ArgumentNullException(nameof(reference));
            if (memo.PointCount != reference.Count)
                throw new ArgumentException("the segment memo is of " + InvariantFormat.Count(memo.PointCount) + " points, the reference has " +
                                            InvariantFormat.Count(reference.Count), nameof(memo));
            if (points.Count != stencils.Count)
                throw new ArgumentException("points (" + points.Count + ") and stencils (" + stencils.Count + ") differ in length");
            var leaking = new bool[points.Count];
            var askers = new List<int>();  // per segment to cast: its position in points, the probe's point index, both ends
            var others = new List<int>();
            var starts = new List<Double3>();
            var ends = new List<Double3>();
            for (int start = 0; start < points.Count; start += PointsPerBatch)
            {
                int stop = Math.Min(points.Count, start + PointsPerBatch);
                askers.Clear();
                others.Clear();
                starts.Clear();
                ends.Clear();
                for (int i = start; i < stop; i++)
                {
                    var s = stencils[i];
                    Ask(reference, memo, probes, i, points[i], s.Probe0, s.Weight0, leaking, askers, others, starts, ends);
                    Ask(reference, memo, probes, i, points[i], s.Probe1, s.Weight1, leaking, askers, others, starts, ends);
                    Ask(reference, memo, probes, i, points[i], s.Probe2, s.Weight2, leaking, askers, others, starts, ends);
                    Ask(reference, memo, probes, i, points[i], s.Probe3, s.Weight3, leaking, askers, others, starts, ends);
                }
                if (askers.Count == 0) continue;
                var free = InUseRays.SegmentsFree(starts.ToArray(), ends.ToArray(), raycaster, "leaks: segment rays", null, CancellationToken.None);
                for (int pair = 0; pair < free.Length; pair++)
                {
                    memo.Remember(points[askers[pair]], others[pair], free[pair]);
                    if (!free[pair]) leaking[askers[pair]] = true;
                }
            }
            return leaking;
        }

        /// <summary>The memo's answer for a weighing pair, or the pair queued to be cast.</summary>
        private static void Ask(ReferenceLighting reference, SegmentMemo memo, int[] probes, int asker, int point, int probe, double weight,
            bool[] leaking, List<int> askers, List<int> others, List<Double3> starts, List<Double3> ends)
        {
            if (!(weight > MinimumWeight)) return;
            if ((uint)probe >= (uint)probes.Length)
                throw new ArgumentOutOfRangeException(nameof(probe), probe, "stencil probe index must be in 0.." + (probes.Length - 1));
            int other = probes[probe];
            if (memo.TryGet(point, other, out bool free))
            {
                if (!free) leaking[asker] = true;
                return;
            }
            askers.Add(asker);
            others.Add(other);
            starts.Add(Double3.FromVector3(reference.GetPosition(point)));
            ends.Add(Double3.FromVector3(reference.GetPosition(other)));
        }

        /// <summary>For each point, whether a probe of its stencil (indices into <paramref name="probePositions"/>) with weight
        /// above <see cref="MinimumWeight"/> is hidden from it; one batched cast for every weighing pair.</summary>
        public static bool[] StencilLeaks(Vector3[] points, Vector3[] probePositions, Stencil[] stencils, IRaycaster raycaster) =>
            StencilLeaks(points, probePositions, stencils, raycaster, null, CancellationToken.None);

        /// <summary>As above, reporting the rays' progress and honouring <paramref name="cancel"/>.</summary>
        internal static bool[] StencilLeaks(Vector3[] points, Vector3[] probePositions, Stencil[] stencils, IRaycaster raycaster,
            ProgressCallback progress, CancellationToken cancel)
        {
            if (points == null) throw new ArgumentNullException(nameof(points));
            if (probePositions == null) throw new ArgumentNullException(nameof(probePositions));
            if (stencils == null) throw new ArgumentNullException(nameof(stencils));
            if (stencils.Length != points.Length)
                throw new ArgumentException("points (" + points.Length + ") and stencils (" + stencils.Length + ") differ in length");
            var owners = new List<int>();
            var starts = new List<Double3>();
            var ends = new List<Double3>();
            for (int n = 0; n < points.Length; n++)
            {
                var s = stencils[n];
                AddPair(n, points[n], probePositions, s.Probe0, s.Weight0, owners, starts, ends);
                AddPair(n, points[n], probePositions, s.Probe1, s.Weight1, owners, starts, ends);
                AddPair(n, points[n], probePositions, s.Probe2, s.Weight2, owners, starts, ends);
                AddPair(n, points[n], probePositions, s.Probe3, s.Weight3, owners, starts, ends);
            }
            // The segment test of in-use.md "Definitions" 2, the one the in-use rule casts.
            var free = InUseRays.SegmentsFree(starts.ToArray(), ends.ToArray(), raycaster, "leaks: segment rays", progress, cancel);
            var leaking = new bool[points.Length];
            for (int pair = 0; pair < free.Length; pair++)
                if (!free[pair]) leaking[owners[pair]] = true;
            return leaking;
        }

        private static void AddPair(int point, Vector3 position, Vector3[] probePositions, int probe, double weight, List<int> owners,
            List<Double3> starts, List<Double3> ends)
        {
            if (!(weight > MinimumWeight)) return;
            if ((uint)probe >= (uint)probePositions.Length)
                throw new ArgumentOutOfRangeException(nameof(probe), probe, "stencil probe index must be in 0.." + (probePositions.Length - 1));
            owners.Add(point);
            starts.Add(Double3.FromVector3(position));
            ends.Add(Double3.FromVector3(probePositions[probe]));
        }
    }
}
