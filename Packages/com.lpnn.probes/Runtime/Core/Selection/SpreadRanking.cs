using System;
using System.Collections.Generic;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Core.Selection
{
    /// <summary>The spread ranking, the default way LPNN scores become probes (Documentation~/selection.md, "Spread
    /// ranking"): importance-weighted farthest-point sampling. The D14 extreme points first, then repeatedly the point
    /// maximising w(p)·D(p) (D = distance to the nearest point already ranked), ties to the lower index.
    ///
    /// Exact and O(N log N) in practice: D only ever shrinks, so a max-heap holding each point's last known w·D is an
    /// upper bound; the top entry is re-checked when it surfaces and re-inserted with its current value when stale, so
    /// the first fresh top is the true maximum (and, the heap breaking ties by index, the lowest index among equals).
    /// The distances are updated locally (<see cref="NearestChosenDistances"/>).</summary>
    public static class SpreadRanking
    {
        /// <summary>All grid points in spread order.</summary>
        public static int[] Rank(EvaluationGrid grid, float[] scores) => Rank(grid, scores, int.MaxValue);

        /// <summary>The first min(<paramref name="count"/>, N) points of the spread order (a budget of K needs only K).</summary>
        public static int[] Rank(EvaluationGrid grid, float[] scores, int count)
        {
            if (grid == null) throw new ArgumentNullException(nameof(grid));
            return Rank(grid.CopyPositions(), scores, count);
        }

        /// <param name="positions">x, y, z per point (float32, as the grid stores them; used in double).</param>
        /// <param name="scores">One score per point: any float, including NaN and ±∞.</param>
        /// <param name="count">How many leading points to return (at most N).</param>
        public static int[] Rank(float[] positions, float[] scores, int count)
        {
            if (positions == null) throw new ArgumentNullException(nameof(positions));
            if (scores == null) throw new ArgumentNullException(nameof(scores));
            if (positions.Length != 3 * scores.Length)
                throw new SelectionException("need one score per point: got " + scores.Length + " scores for " + positions.Length / 3 + " points");
            if (count < 0) throw new SelectionException("cannot rank a negative number (" + count + ") of points");
            int pointCount = scores.Length;
            CheckFinite(positions);
            int length = Math.Min(count, pointCount);
            var order = new int[length];
            if (length == 0) return order;

            double[] weights = SpreadWeights.Compute(scores);
            var x = new double[pointCount];
            var y = new double[pointCount];
            var z = new double[pointCount];
            for (int n = 0; n < pointCount; n++)
            {
                x[n] = positions[3 * n];
                y[n] = positions[3 * n + 1];
                z[n] = positions[3 * n + 2];
            }
            var distances = new NearestChosenDistances(x, y, z);
            var chosen = new bool[pointCount];
            int ranked = 0;
            foreach (int seed in ExtremeSeeds.Find(positions))
            {
                if (ranked == length) return order;
                order[ranked++] = seed;
                chosen[seed] = true;
                distances.Add(seed);
            }

            var heap = new RankHeap(pointCount - ranked);
            for (int n = 0; n < pointCount; n++)
                if (!chosen[n]) heap.Push(weights[n] * distances[n], n);
            while (ranked < length)
            {
                int point = heap.TopPoint;
                double stored = heap.TopValue;
                double current = weights[point] * distances[point];
                heap.Pop();
                if (current != stored)
                {
                    // Stale: D shrank since the entry was pushed; its current value is the new upper bound.
                    heap.Push(current, point);
                    continue;
                }
                order[ranked++] = point;
                distances.Add(point);
            }
            return order;
        }

        private static void CheckFinite(float[] positions)
        {
            for (int c = 0; c < positions.Length; c++)
            {
                float v = positions[c];
                if (float.IsNaN(v) || float.IsInfinity(v))
                    throw new SelectionException("point " + c / 3 + " has a non-finite position coordinate (" + InvariantFormat.Number(v) +
                                                 "); every evaluation point needs a finite position");
            }
        }
    }
}
