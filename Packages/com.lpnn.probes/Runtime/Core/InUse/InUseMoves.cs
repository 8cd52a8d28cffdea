using System;
using System.Collections.Generic;
using System.Threading;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Core.InUse
{
    /// <summary>The directed moves between in-band lattice neighbours (Documentation~/in-use.md "Definitions" 4): vertical
    /// ones when the segment is free, horizontal ones when it is free and the floor profile is walkable that way.</summary>
    internal static class InUseMoves
    {
        /// <summary>Every allowed move, as parallel source and target point indices: floor profiles through
        /// <paramref name="floorRaycaster"/>, segments through <paramref name="segmentRaycaster"/>.</summary>
        public static void Collect(EvaluationGrid grid, IRaycaster floorRaycaster, IRaycaster segmentRaycaster, InUseParameters parameters, InUseBand band,
            List<int> sources, List<int> targets, ProgressCallback progress, CancellationToken cancel)
        {
            var lower = new List<int>();
            var upper = new List<int>();
            Pairs(grid, band.InBand, 1, lower, upper);
            var both = new bool[lower.Count];
            for (int p = 0; p < both.Length; p++) both[p] = true;
            AddFreeMoves(grid, segmentRaycaster, lower, upper, both, both, sources, targets, "in use: vertical move rays", progress, cancel);

            var first = new List<int>();
            var second = new List<int>();
            Pairs(grid, band.InBand, 0, first, second);
            Pairs(grid, band.InBand, 2, first, second);
            var forward = new bool[first.Count];
            var backward = new bool[first.Count];
            Profiles(grid, floorRaycaster, parameters, band.FloorHeights, first, second, forward, backward, progress, cancel);
            AddFreeMoves(grid, segmentRaycaster, first, second, forward, backward, sources, targets, "in use: horizontal move rays", progress, cancel);
        }

        /// <summary>The pairs (p, p + 1 along axis) with both points in band.</summary>
        private static void Pairs(EvaluationGrid grid, bool[] inBand, int axis, List<int> first, List<int> second)
        {
            for (int p = 0; p < grid.Count; p++)
            {
                if (!inBand[p]) continue;
                int q = grid.Neighbour(p, axis, 1);
                if (q < 0 || !inBand[q]) continue;
                first.Add(p);
                second.Add(q);
            }
        }

        /// <summary>Adds first → second where <paramref name="forward"/> allows it, and second → first where
        /// <paramref name="backward"/> does, each when its own segment (cast from its source) is free.</summary>
        private static void AddFreeMoves(EvaluationGrid grid, IRaycaster raycaster, List<int> first, List<int> second, bool[] forward,
            bool[] backward, List<int> sources, List<int> targets, string stage, ProgressCallback progress, CancellationToken cancel)
        {
            var moveSources = new List<int>();
            var moveTargets = new List<int>();
            for (int p = 0; p < first.Count; p++)
            {
                if (forward[p])
                {
                    moveSources.Add(first[p]);
                    moveTargets.Add(second[p]);
                }
                if (backward[p])
                {
                    moveSources.Add(second[p]);
                    moveTargets.Add(first[p]);
                }
            }
            var starts = new Double3[moveSources.Count];
            var ends = new Double3[moveSources.Count];
            for (int m = 0; m < starts.Length; m++)
            {
                starts[m] = Double3.FromVector3(grid.GetPosition(moveSources[m]));
                ends[m] = Double3.FromVector3(grid.GetPosition(moveTargets[m]));
            }
            var free = InUseRays.SegmentsFree(starts, ends, raycaster, stage, progress, cancel);
            for (int m = 0; m < free.Length; m++)
            {
                if (!free[m]) continue;
                sources.Add(moveSources[m]);
                targets.Add(moveTargets[m]);
            }
        }

        /// <summary>Each horizontal pair's floor profile, sampled once from the point with the lower id toward the higher
        /// (x_i = p + (i/M)(q − p)), read forwards for p → q and backwards for q → p: every interior sample hits a
        /// walkable floor within H and every rise along the walk is at most s + (h/M)·tan θ. Sampled in batches of pairs so
        /// at most <see cref="InUseRays.RaysPerBatch"/> samples are held at once.</summary>
        private static void Profiles(EvaluationGrid grid, IRaycaster raycaster, InUseParameters parameters, double[] floorHeights,
            List<int> first, List<int> second, bool[] forward, bool[] backward, ProgressCallback progress, CancellationToken cancel)
        {
            int intervals = InUseParameters.ProfileIntervals(grid.CellSize);
            double riseLimit = parameters.RiseLimit(grid.CellSize);
            int interior = intervals - 1;
            int pairsPerBatch = interior == 0 ? Math.Max(1, first.Count) : Math.Max(1, InUseRays.RaysPerBatch / interior);
            long total = (long)first.Count * interior;
            var profile = new double[intervals + 1];
            for (int begin = 0; begin < first.Count; begin += pairsPerBatch)
            {
                int end = Math.Min(first.Count, begin + pairsPerBatch);
                var samples = new Double3[(end - begin) * interior];
                for (int pair = begin; pair < end; pair++)
                {
                    var p = Double3.FromVector3(grid.GetPosition(first[pair]));
                    var step = Double3.FromVector3(grid.GetPosition(second[pair])) - p;
                    for (int i = 1; i < intervals; i++) samples[(pair - begin) * interior + i - 1] = p + ((double)i / intervals) * step;
                }
                var heights = interior == 0 ? new double[0]
                    : InUseRays.FloorHeights(samples, raycaster, parameters, "in use: floor profile rays", (long)begin * interior, total,
                        progress, cancel);
                for (int pair = begin; pair < end; pair++)
                {
                    profile[0] = floorHeights[first[pair]];
                    profile[intervals] = floorHeights[second[pair]];
                    for (int i = 1; i < intervals; i++) profile[i] = heights[(pair - begin) * interior + i - 1];
                    bool up = true, down = true;
                    for (int i = 0; i < intervals; i++)
                    {
                        double rise = profile[i + 1] - profile[i];
                        // NaN (an interior sample without a walkable floor) fails both comparisons: no move either way.
                        up &= rise <= riseLimit;
                        down &= -rise <= riseLimit;
                    }
                    forward[pair] = up;
                    backward[pair] = down;
                }
            }
        }
    }
}
