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
    /// Exact and O(N log N) in practice (<see cref="FarthestPointSampling"/>).</summary>
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
            if (length == 0) return new int[0];

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
            return FarthestPointSampling.Rank(x, y, z, weights, ExtremeSeeds.Find(positions), length);
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
