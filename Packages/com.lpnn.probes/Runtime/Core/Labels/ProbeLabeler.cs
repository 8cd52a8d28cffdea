using System;
using System.Collections.Generic;
using System.Numerics;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Core.Labels
{
    /// <summary>Training labels from a ground-truth probe set (the thesis' rule): a point is positive when a
    /// probe lies in its cell. O(points + probes): each probe is mapped to its cell id and looked up.</summary>
    internal static class ProbeLabeler
    {
        public sealed class Result
        {
            /// <summary>One label per grid point: 1 when at least one probe lies in its cell.</summary>
            public byte[] Labels { get; }
            public int ProbesMatched { get; }
            /// <summary>Probes whose cell is not an evaluation point (outside the volume).</summary>
            public int ProbesOutside { get; }
            public int PositivePoints { get; }

            public Result(byte[] labels, int matched, int outside, int positive)
            {
                Labels = labels;
                ProbesMatched = matched;
                ProbesOutside = outside;
                PositivePoints = positive;
            }
        }

        /// <summary>Cells are half-open, [p − h/2, p + h/2) per axis, so each probe belongs to exactly one.</summary>
        public static Result Label(EvaluationGrid grid, IReadOnlyList<Vector3> probePositions)
        {
            if (grid == null) throw new ArgumentNullException(nameof(grid));
            if (probePositions == null) throw new ArgumentNullException(nameof(probePositions));
            var labels = new byte[grid.Count];
            int matched = 0, outside = 0, positive = 0;
            double h = grid.CellSize;
            for (int p = 0; p < probePositions.Count; p++)
            {
                var q = probePositions[p];
                if (!Double3.FromVector3(q).IsFinite)
                    throw new LpnnException("ground-truth probe " + p + " has a non-finite position " + InvariantFormat.Vector(q) +
                                            "; fix or remove it in the LightProbeGroup");
                int index = LatticeId.TryCellOf(Double3.FromVector3(q), h, out var id) ? grid.IndexOf(id) : -1;
                if (index < 0)
                {
                    outside++;
                    continue;
                }
                matched++;
                if (labels[index] == 0) positive++;
                labels[index] = 1;
            }
            return new Result(labels, matched, outside, positive);
        }
    }
}
