using System;
using System.Collections.Generic;
using Lpnn.Probes.Core.Features;

namespace Lpnn.Probes.Core.Selection
{
    /// <summary>The seeds of the spread ranking (Documentation~/selection.md, "Spread ranking" step 2): for each D14
    /// direction d, in order, the point maximising d·p, ties to the lower index, repeats dropped. They are the extreme
    /// corners of the point set, so the first probes already enclose the volume.
    ///
    /// The arithmetic is fixed so that C# and Python (lpnn.core.spread) break every tie alike: the float32
    /// coordinates widened to double, d·p = x·dx + y·dy + z·dz summed left to right.</summary>
    internal static class ExtremeSeeds
    {
        /// <summary>Seed point indices, first occurrence kept; <paramref name="positions"/> holds x, y, z per point.</summary>
        public static int[] Find(float[] positions)
        {
            if (positions == null) throw new ArgumentNullException(nameof(positions));
            int count = positions.Length / 3;
            var seeds = new List<int>(DirectionSets.D14.GetLength(0));
            if (count == 0) return seeds.ToArray();
            for (int d = 0; d < DirectionSets.D14.GetLength(0); d++)
            {
                double dx = DirectionSets.D14[d, 0], dy = DirectionSets.D14[d, 1], dz = DirectionSets.D14[d, 2];
                int best = 0;
                double bestKey = Key(positions, 0, dx, dy, dz);
                for (int n = 1; n < count; n++)
                {
                    double key = Key(positions, n, dx, dy, dz);
                    if (key > bestKey)
                    {
                        bestKey = key;
                        best = n;
                    }
                }
                if (!seeds.Contains(best)) seeds.Add(best);
            }
            return seeds.ToArray();
        }

        private static double Key(float[] positions, int n, double dx, double dy, double dz)
        {
            double x = positions[3 * n], y = positions[3 * n + 1], z = positions[3 * n + 2];
            return x * dx + y * dy + z * dz;
        }
    }
}
