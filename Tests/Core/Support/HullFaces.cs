using System;
using System.Collections.Generic;
using System.Numerics;

namespace Lpnn.Probes.Core.Tests.Support
{
    /// <summary>Independent checks of hull geometry for the placement-error tests: the boundary triangles of a set of
    /// tetrahedra and the distance from a point to a triangle (by projection onto the plane, else the nearest edge).</summary>
    public static class HullFaces
    {
        public static List<int[]> Of(int[] tetrahedra)
        {
            var uses = new Dictionary<string, int[]>();
            var count = new Dictionary<string, int>();
            for (int t = 0; t < tetrahedra.Length; t += 4)
            {
                for (int skip = 0; skip < 4; skip++)
                {
                    var face = new List<int>();
                    for (int k = 0; k < 4; k++) if (k != skip) face.Add(tetrahedra[t + k]);
                    face.Sort();
                    string key = string.Join(",", face);
                    uses[key] = face.ToArray();
                    count[key] = count.TryGetValue(key, out int c) ? c + 1 : 1;
                }
            }
            var hull = new List<int[]>();
            foreach (var entry in count)
                if (entry.Value == 1) hull.Add(uses[entry.Key]);
            return hull;
        }

        public static double DistanceToTriangle(Vector3 pf, Vector3 af, Vector3 bf, Vector3 cf)
        {
            var p = new[] { (double)pf.X, pf.Y, pf.Z };
            var a = new[] { (double)af.X, af.Y, af.Z };
            var b = new[] { (double)bf.X, bf.Y, bf.Z };
            var c = new[] { (double)cf.X, cf.Y, cf.Z };
            var n = Cross(Sub(b, a), Sub(c, a));
            double nn = Dot(n, n);
            double t = Dot(Sub(p, a), n) / nn;
            var q = new[] { p[0] - t * n[0], p[1] - t * n[1], p[2] - t * n[2] };
            // Inside the triangle when q is on the inner side of all three edges.
            bool inside = Dot(Cross(Sub(b, a), Sub(q, a)), n) >= 0 && Dot(Cross(Sub(c, b), Sub(q, b)), n) >= 0 && Dot(Cross(Sub(a, c), Sub(q, c)), n) >= 0;
            if (inside) return Math.Abs(t) * Math.Sqrt(nn);
            return Math.Min(SegmentDistance(p, a, b), Math.Min(SegmentDistance(p, b, c), SegmentDistance(p, c, a)));
        }

        private static double SegmentDistance(double[] p, double[] a, double[] b)
        {
            var ab = Sub(b, a);
            double t = Math.Max(0, Math.Min(1, Dot(Sub(p, a), ab) / Dot(ab, ab)));
            var d = new[] { a[0] + t * ab[0] - p[0], a[1] + t * ab[1] - p[1], a[2] + t * ab[2] - p[2] };
            return Math.Sqrt(Dot(d, d));
        }

        private static double[] Sub(double[] u, double[] v) => new[] { u[0] - v[0], u[1] - v[1], u[2] - v[2] };
        private static double Dot(double[] u, double[] v) => u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
        private static double[] Cross(double[] u, double[] v) => new[] { u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0] };
    }
}
