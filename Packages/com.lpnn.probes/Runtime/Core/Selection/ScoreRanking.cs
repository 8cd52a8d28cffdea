using System;

namespace Lpnn.Probes.Core.Selection
{
    /// <summary>Orders points by score and remaps scores to [0, 1] (Documentation~/selection.md). Every
    /// division is guarded: all-equal, NaN and infinite scores are well defined.</summary>
    internal static class ScoreRanking
    {
        /// <summary>Point indices, best first: +∞, then finite scores descending, then −∞, then NaN; equal
        /// scores by lower index (so ties never duplicate or reorder between runs).</summary>
        public static int[] Rank(float[] scores)
        {
            if (scores == null) throw new ArgumentNullException(nameof(scores));
            var order = new int[scores.Length];
            for (int n = 0; n < order.Length; n++) order[n] = n;
            Array.Sort(order, (a, b) => Compare(scores, a, b));
            return order;
        }

        private static int Category(float score)
        {
            if (float.IsNaN(score)) return 3;
            if (float.IsPositiveInfinity(score)) return 0;
            if (float.IsNegativeInfinity(score)) return 2;
            return 1;
        }

        private static int Compare(float[] scores, int a, int b)
        {
            float x = scores[a], y = scores[b];
            int cx = Category(x), cy = Category(y);
            if (cx != cy) return cx.CompareTo(cy);
            if (cx == 1 && x != y) return x > y ? -1 : 1;
            return a.CompareTo(b);
        }

        /// <summary>Min-max remap of the finite scores to [0, 1] in double; all-equal finite scores map to 1
        /// (no point is less important than another); +∞ → 1, −∞ → 0, NaN → 0.</summary>
        public static double[] Remap(float[] scores)
        {
            if (scores == null) throw new ArgumentNullException(nameof(scores));
            double lo = double.PositiveInfinity, hi = double.NegativeInfinity;
            foreach (float s in scores)
            {
                if (float.IsNaN(s) || float.IsInfinity(s)) continue;
                if (s < lo) lo = s;
                if (s > hi) hi = s;
            }
            double range = hi - lo;
            var result = new double[scores.Length];
            for (int n = 0; n < scores.Length; n++)
            {
                float s = scores[n];
                if (float.IsNaN(s) || float.IsNegativeInfinity(s)) result[n] = 0;
                else if (float.IsPositiveInfinity(s)) result[n] = 1;
                else result[n] = range > 0 ? (s - lo) / range : 1;
            }
            return result;
        }
    }
}
