using System;
using System.Numerics;

namespace Lpnn.Probes.Core.Features
{
    /// <summary>The fixed direction sets of Documentation~/features.md (no randomness, ever).</summary>
    internal static class DirectionSets
    {
        /// <summary>Lighting directions: 6 axes, then the 8 cube diagonals.</summary>
        public static readonly double[,] D14 = Build(false);

        /// <summary>Ray directions: D14, then the 12 cube edge directions.</summary>
        public static readonly double[,] D26 = Build(true);

        private static double[,] Build(bool withEdges)
        {
            var rows = new double[withEdges ? 26 : 14, 3];
            int n = 0;
            double[][] axes =
            {
                new[] { 1.0, 0, 0 }, new[] { -1.0, 0, 0 }, new[] { 0, 1.0, 0 },
                new[] { 0, -1.0, 0 }, new[] { 0, 0, 1.0 }, new[] { 0, 0, -1.0 },
            };
            foreach (var a in axes) Put(rows, n++, a[0], a[1], a[2]);
            double d = 1 / Math.Sqrt(3);
            foreach (int sx in new[] { 1, -1 })
                foreach (int sy in new[] { 1, -1 })
                    foreach (int sz in new[] { 1, -1 })
                        Put(rows, n++, sx * d, sy * d, sz * d);
            if (!withEdges) return rows;
            double e = 1 / Math.Sqrt(2);
            foreach (int s1 in new[] { 1, -1 })
                foreach (int s2 in new[] { 1, -1 })
                    Put(rows, n++, s1 * e, s2 * e, 0);
            foreach (int s1 in new[] { 1, -1 })
                foreach (int s2 in new[] { 1, -1 })
                    Put(rows, n++, s1 * e, 0, s2 * e);
            foreach (int s1 in new[] { 1, -1 })
                foreach (int s2 in new[] { 1, -1 })
                    Put(rows, n++, 0, s1 * e, s2 * e);
            return rows;
        }

        private static void Put(double[,] rows, int n, double x, double y, double z)
        {
            rows[n, 0] = x;
            rows[n, 1] = y;
            rows[n, 2] = z;
        }

        public static Vector3 Direction(double[,] set, int index) =>
            new Vector3((float)set[index, 0], (float)set[index, 1], (float)set[index, 2]);
    }
}
