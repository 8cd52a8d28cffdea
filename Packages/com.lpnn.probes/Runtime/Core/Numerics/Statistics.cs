using System;
using System.Collections.Generic;

namespace Lpnn.Probes.Core.Numerics
{
    /// <summary>Order statistics shared by the features (scene scale) and the selection (spread weights).</summary>
    internal static class Statistics
    {
        /// <summary>Quickselect of the indices <paramref name="order"/>[lo..hi] by the key values[stride × index + offset], so
        /// that position <paramref name="nth"/> splits them (deterministic median-of-three pivots; O(n) on average, so a k-d
        /// tree built by it takes O(N log N)). Shared by the k-d trees of the selection and the refinement's tie heights.</summary>
        public static void SelectByKey(int[] order, double[] values, int stride, int offset, int lo, int hi, int nth)
        {
            while (hi > lo)
            {
                int mid = lo + (hi - lo) / 2;
                double a = values[stride * order[lo] + offset], b = values[stride * order[mid] + offset], c = values[stride * order[hi] + offset];
                double pivot = Math.Max(Math.Min(a, b), Math.Min(Math.Max(a, b), c));
                int i = lo, j = hi;
                while (i <= j)
                {
                    while (values[stride * order[i] + offset] < pivot) i++;
                    while (values[stride * order[j] + offset] > pivot) j--;
                    if (i > j) break;
                    int t = order[i];
                    order[i] = order[j];
                    order[j] = t;
                    i++;
                    j--;
                }
                if (nth <= j) hi = j;
                else if (nth >= i) lo = i;
                else return;
            }
        }

        /// <summary>The middle value, or the mean of the two middle values for an even count; the input is not changed.</summary>
        public static double Median(IReadOnlyList<double> values)
        {
            if (values == null || values.Count == 0) throw new ArgumentException("the median needs at least one value", nameof(values));
            var copy = new double[values.Count];
            for (int n = 0; n < copy.Length; n++)
            {
                copy[n] = values[n];
                if (double.IsNaN(copy[n])) throw new ArgumentException("value " + n + " is NaN: the median of numbers only", nameof(values));
            }
            int middle = copy.Length / 2;
            double upper = SelectInPlace(copy, middle);
            if (copy.Length % 2 == 1) return upper;
            // After selection everything before `middle` is ≤ upper: the lower middle value is their maximum.
            double lower = double.NegativeInfinity;
            for (int n = 0; n < middle; n++) lower = Math.Max(lower, copy[n]);
            return (lower + upper) / 2;
        }

        /// <summary>The k-th smallest value (0-based), reordering <paramref name="values"/> so that every value before
        /// position k is ≤ it and every value after is ≥ it: quickselect with median-of-three pivots, O(N) on average (a
        /// full sort of 10⁶ doubles costs ~0.8 s under Mono; the insertion ranking takes 42 medians of N values).</summary>
        private static double SelectInPlace(double[] a, int k)
        {
            int lo = 0, hi = a.Length - 1;
            while (hi > lo)
            {
                int mid = lo + (hi - lo) / 2;
                double x = a[lo], y = a[mid], z = a[hi];
                double pivot = Math.Max(Math.Min(x, y), Math.Min(Math.Max(x, y), z));
                int i = lo, j = hi;
                while (i <= j)
                {
                    while (a[i] < pivot) i++;
                    while (a[j] > pivot) j--;
                    if (i > j) break;
                    double t = a[i];
                    a[i] = a[j];
                    a[j] = t;
                    i++;
                    j--;
                }
                if (k <= j) hi = j;
                else if (k >= i) lo = i;
                else break;
            }
            return a[k];
        }
    }
}
