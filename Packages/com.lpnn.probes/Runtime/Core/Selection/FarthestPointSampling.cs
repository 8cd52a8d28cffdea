using System.Collections.Generic;

namespace Lpnn.Probes.Core.Selection
{
    /// <summary>Importance-weighted farthest-point sampling, the loop behind the spread ranking (Documentation~/selection.md)
    /// and the insertion ranking's typical tetrahedron (quality.md §5): the seeds in order (repeats dropped), then
    /// repeatedly the point maximising w(p)·D(p), D = distance to the nearest point already ranked, ties to the lower index.
    ///
    /// Exact and O(N log N) in practice: D only ever shrinks, so a max-heap holding each point's last known w·D is an
    /// upper bound; the top entry is re-checked when it surfaces and re-inserted with its current value when stale, so
    /// the first fresh top is the true maximum (and, the heap breaking ties by index, the lowest index among equals).
    /// The distances are updated locally (<see cref="NearestChosenDistances"/>).</summary>
    internal static class FarthestPointSampling
    {
        /// <param name="x">Coordinates per point (double; the caller decides the frame).</param>
        /// <param name="weights">w(p) ≥ 0, finite, one per point.</param>
        /// <param name="seeds">Ranked first, in order; repeats are dropped.</param>
        /// <param name="length">How many leading points to return (at most the point count).</param>
        public static int[] Rank(double[] x, double[] y, double[] z, double[] weights, IEnumerable<int> seeds, int length)
        {
            int pointCount = x.Length;
            var order = new int[length];
            if (length == 0) return order;
            var distances = new NearestChosenDistances(x, y, z);
            var chosen = new bool[pointCount];
            int ranked = 0;
            foreach (int seed in seeds)
            {
                if (ranked == length) return order;
                if (chosen[seed]) continue;
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
    }
}
