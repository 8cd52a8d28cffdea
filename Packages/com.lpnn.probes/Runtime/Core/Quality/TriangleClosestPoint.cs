using System;

namespace Lpnn.Probes.Core.Quality
{
    /// <summary>Barycentric weights of the point of a triangle closest to a query point, by Voronoi regions
    /// (Ericson, Real-Time Collision Detection §5.1.5) — the same region tests, in the same order, as the Python
    /// reference (lpnn.quality.metric.hull_projection), so both pick the same region at region boundaries.</summary>
    internal static class TriangleClosestPoint
    {
        /// <summary>Weights (u, v, w) ≥ 0, sum 1, of the closest point u·a + v·b + w·c to p. Corners are x, y, z triples
        /// at the given offsets of <paramref name="points"/>.</summary>
        public static void Weights(double px, double py, double pz, double[] points, int a, int b, int c,
            out double u, out double v, out double w)
        {
            double ax = points[3 * a], ay = points[3 * a + 1], az = points[3 * a + 2];
            double bx = points[3 * b], by = points[3 * b + 1], bz = points[3 * b + 2];
            double cx = points[3 * c], cy = points[3 * c + 1], cz = points[3 * c + 2];
            double abx = bx - ax, aby = by - ay, abz = bz - az;
            double acx = cx - ax, acy = cy - ay, acz = cz - az;
            double apx = px - ax, apy = py - ay, apz = pz - az;
            double d1 = abx * apx + aby * apy + abz * apz, d2 = acx * apx + acy * apy + acz * apz;
            double bpx = px - bx, bpy = py - by, bpz = pz - bz;
            double d3 = abx * bpx + aby * bpy + abz * bpz, d4 = acx * bpx + acy * bpy + acz * bpz;
            double cpx = px - cx, cpy = py - cy, cpz = pz - cz;
            double d5 = abx * cpx + aby * cpy + abz * cpz, d6 = acx * cpx + acy * cpy + acz * cpz;
            double vc = d1 * d4 - d3 * d2;
            double vb = d5 * d2 - d1 * d6;
            double va = d3 * d6 - d5 * d4;
            if (d1 <= 0 && d2 <= 0) { u = 1; v = 0; w = 0; }
            else if (d3 >= 0 && d4 <= d3) { u = 0; v = 1; w = 0; }
            else if (vc <= 0 && d1 >= 0 && d3 <= 0)
            {
                double t = SafeRatio(d1, d1 - d3);
                u = 1 - t; v = t; w = 0;
            }
            else if (d6 >= 0 && d5 <= d6) { u = 0; v = 0; w = 1; }
            else if (vb <= 0 && d2 >= 0 && d6 <= 0)
            {
                double t = SafeRatio(d2, d2 - d6);
                u = 1 - t; v = 0; w = t;
            }
            else if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0)
            {
                double t = SafeRatio(d4 - d3, (d4 - d3) + (d5 - d6));
                u = 0; v = 1 - t; w = t;
            }
            else
            {
                double total = va + vb + vc;
                v = SafeRatio(vb, total);
                w = SafeRatio(vc, total);
                u = 1 - v - w;
            }
            u = Math.Max(0, u);
            v = Math.Max(0, v);
            w = Math.Max(0, w);
            // Every branch sums to 1 before clamping, which only removes rounding-level negatives: the sum stays positive.
            double sum = u + v + w;
            u /= sum;
            v /= sum;
            w /= sum;
        }

        /// <summary>A degenerate (zero-length) edge or triangle gives a zero denominator; any finite answer is then a
        /// point of the triangle, so divide by 1 instead.</summary>
        private static double SafeRatio(double numerator, double denominator) => numerator / (denominator != 0 ? denominator : 1);
    }
}
