using System;
using System.Collections.Generic;
using Lpnn.Probes.Core.Features;

namespace Lpnn.Probes.Core.Tests.Support
{
    /// <summary>Documentation~/selection.md's spread ranking written as plainly as possible — O(N²), no heap, no tree —
    /// to check the fast implementation against. Shares nothing with it but the D14 table.</summary>
    public static class NaiveSpreadRanking
    {
        public static int[] Rank(float[] positions, float[] scores)
        {
            int n = scores.Length;
            var s = new double[n];
            for (int p = 0; p < n; p++)
                s[p] = float.IsNaN(scores[p]) ? 1e-6 : Math.Min(1.0, Math.Max(1e-6, (double)scores[p]));
            var sorted = (double[])s.Clone();
            Array.Sort(sorted);
            double median = n == 0 ? 1 : n % 2 == 1 ? sorted[n / 2] : (sorted[n / 2 - 1] + sorted[n / 2]) / 2;
            var w = new double[n];
            for (int p = 0; p < n; p++) w[p] = Math.Sqrt(s[p] / median);

            var order = new List<int>();
            var chosen = new bool[n];
            for (int d = 0; d < 14 && n > 0; d++)
            {
                int best = -1;
                double bestKey = double.NegativeInfinity;
                for (int p = 0; p < n; p++)
                {
                    double key = (double)positions[3 * p] * DirectionSets.D14[d, 0] + (double)positions[3 * p + 1] * DirectionSets.D14[d, 1] +
                                 (double)positions[3 * p + 2] * DirectionSets.D14[d, 2];
                    if (best < 0 || key > bestKey)
                    {
                        best = p;
                        bestKey = key;
                    }
                }
                if (!chosen[best])
                {
                    chosen[best] = true;
                    order.Add(best);
                }
            }
            var distance = new double[n];
            for (int p = 0; p < n; p++)
            {
                distance[p] = double.PositiveInfinity;
                foreach (int c in order) distance[p] = Math.Min(distance[p], Distance(positions, p, c));
            }
            while (order.Count < n)
            {
                int best = -1;
                for (int p = 0; p < n; p++)
                    if (!chosen[p] && (best < 0 || w[p] * distance[p] > w[best] * distance[best])) best = p;
                chosen[best] = true;
                order.Add(best);
                for (int p = 0; p < n; p++) distance[p] = Math.Min(distance[p], Distance(positions, p, best));
            }
            return order.ToArray();
        }

        private static double Distance(float[] positions, int a, int b)
        {
            double dx = (double)positions[3 * a] - positions[3 * b];
            double dy = (double)positions[3 * a + 1] - positions[3 * b + 1];
            double dz = (double)positions[3 * a + 2] - positions[3 * b + 2];
            return Math.Sqrt(dx * dx + dy * dy + dz * dz);
        }
    }
}
