using System;
using System.Collections.Generic;
using System.Linq;
using System.Numerics;
using Lpnn.Probes.Core.Quality;

namespace Lpnn.Probes.Core.Tests.Support
{
    /// <summary>A small Delaunay tetrahedraliser for tests only (Unity's is not available here): Bowyer–Watson in double
    /// with a symbolic vertex at infinity, so the convex hull is always complete (a finite "super tetrahedron" loses
    /// hull slivers of nearly flat faces). Every insertion scans all tetrahedra for conflicts: O(n²), fine for the few
    /// hundred points tests use. Inputs must be in general position (no 4 coplanar, no 5 cospherical points):
    /// tests jitter grid positions, so the Delaunay tetrahedralisation is unique.
    ///
    /// <see cref="TieBroken"/> lifts each point by a tie height as well (a regular triangulation, the power test in place of
    /// the sphere test), so that a lattice, cospherical everywhere, gets the one tetrahedralisation Python's tie-broken
    /// Qhull gives (quality.md §1): the batched refinement's star refills must reproduce it.</summary>
    public sealed class BowyerWatsonDelaunay : ITetrahedralizer
    {
        private const int Infinite = -1;
        private readonly Func<Vector3, double> _tieHeight;

        public BowyerWatsonDelaunay() { }

        private BowyerWatsonDelaunay(Func<Vector3, double> tieHeight) { _tieHeight = tieHeight; }

        /// <summary>Lifts every position of <paramref name="reference"/> by its tie height (TieBreak, in world units²);
        /// positions that are not evaluation points are refused. <paramref name="otherwise"/>: by the largest tie height
        /// less its own instead, a tetrahedraliser that breaks every tie the other way.</summary>
        internal static BowyerWatsonDelaunay TieBroken(ReferenceLighting reference, bool otherwise = false)
        {
            var height = new Dictionary<Vector3, double>();
            double scale = reference.Frame.Scale, top = reference.TieHeights.Max();
            for (int p = 0; p < reference.Count; p++)
                height[reference.GetPosition(p)] = (otherwise ? top - reference.TieHeights[p] : reference.TieHeights[p]) * scale * scale;
            return new BowyerWatsonDelaunay(position => height.TryGetValue(position, out double h) ? h
                : throw new ArgumentException("position " + position + " is not an evaluation point"));
        }

        /// <summary>Calls so far (tests count them).</summary>
        public int Calls;

        public int[] Tetrahedralize(Vector3[] positions)
        {
            if (positions == null) throw new ArgumentNullException(nameof(positions));
            Calls++;
            var points = new double[positions.Length, 3];
            var heights = new double[positions.Length];
            for (int n = 0; n < positions.Length; n++)
            {
                points[n, 0] = positions[n].X;
                points[n, 1] = positions[n].Y;
                points[n, 2] = positions[n].Z;
                if (_tieHeight != null) heights[n] = _tieHeight(positions[n]);
            }
            return Tetrahedralize(points, _tieHeight == null ? null : heights);
        }

        /// <summary>Finite tetrahedra (4 indices each, positively oriented) of points given as rows of x, y, z.</summary>
        public static int[] Tetrahedralize(double[,] points) => Tetrahedralize(points, null);

        /// <summary>As the overload, each point lifted by its height as well (a regular triangulation); a point in the
        /// plane of a hull face then conflicts with the outside beyond it when it lies in the face's power circle (a
        /// lattice's hull faces are planar with many points, and only that rule splits them as the lifting does).</summary>
        public static int[] Tetrahedralize(double[,] points, double[] heights)
        {
            int count = points.GetLength(0);
            if (count < 4) throw new ArgumentException("need at least 4 points, got " + count);
            int[] first = FirstTetrahedron(points);
            var tets = new List<int[]>();
            int a = first[0], b = first[1], c = first[2], d = first[3];
            if (Orient(points, a, b, c, d) < 0) { int t = c; c = d; d = t; }
            var initial = new[] { a, b, c, d };
            tets.Add(initial);
            // The four hull faces, each closed by the vertex at infinity on its outer side.
            foreach (var face in InwardFaces(initial)) tets.Add(new[] { face[0], face[2], face[1], Infinite });
            var inserted = new HashSet<int>(first);
            for (int p = 0; p < count; p++)
            {
                if (inserted.Contains(p)) continue;
                Insert(points, heights, tets, p);
            }
            var result = new List<int>();
            foreach (var t in tets)
                if (Array.IndexOf(t, Infinite) < 0) result.AddRange(t);
            return result.ToArray();
        }

        private static int[] FirstTetrahedron(double[,] points)
        {
            int count = points.GetLength(0);
            for (int i = 1; i < count; i++)
            for (int j = i + 1; j < count; j++)
            for (int k = j + 1; k < count; k++)
                if (Orient(points, 0, i, j, k) != 0) return new[] { 0, i, j, k };
            throw new ArgumentException("all points lie in one plane");
        }

        private static void Insert(double[,] points, double[] heights, List<int[]> tets, int p)
        {
            var conflicting = new List<int[]>();
            var keep = new List<int[]>();
            foreach (var t in tets) (InConflict(points, heights, t, p) ? conflicting : keep).Add(t);
            if (conflicting.Count == 0) throw new InvalidOperationException("point " + p + " conflicts with no tetrahedron (duplicate point?)");
            // The cavity's boundary: faces of conflicting tetrahedra not shared with another one. Each is oriented with
            // its tetrahedron on the positive side, and the cavity is star-shaped from p, so (face, p) is positive.
            var faceUses = new Dictionary<string, int>();
            var faces = new List<int[]>();
            foreach (var t in conflicting)
                foreach (var face in InwardFaces(t))
                {
                    string key = Key(face);
                    faceUses[key] = faceUses.TryGetValue(key, out int uses) ? uses + 1 : 1;
                    faces.Add(face);
                }
            tets.Clear();
            tets.AddRange(keep);
            foreach (var face in faces)
                if (faceUses[Key(face)] == 1) tets.Add(new[] { face[0], face[1], face[2], p });
        }

        /// <summary>The faces opposite each vertex, ordered so that the opposite vertex lies on their positive side.</summary>
        private static IEnumerable<int[]> InwardFaces(int[] t)
        {
            yield return new[] { t[1], t[3], t[2] };
            yield return new[] { t[0], t[2], t[3] };
            yield return new[] { t[0], t[3], t[1] };
            yield return new[] { t[0], t[1], t[2] };
        }

        private static string Key(int[] face)
        {
            var sorted = (int[])face.Clone();
            Array.Sort(sorted);
            return sorted[0] + "," + sorted[1] + "," + sorted[2];
        }

        /// <summary>p lies strictly inside the circumsphere (finite tetrahedron) or strictly beyond the hull face (a
        /// tetrahedron with the vertex at infinity, whose "circumsphere" is that open half-space).</summary>
        private static bool InConflict(double[,] points, double[] heights, int[] t, int p)
        {
            int at = Array.IndexOf(t, Infinite);
            if (at < 0) return InSphere(points, heights, t[0], t[1], t[2], t[3], p) > 0;
            // Moving the infinite vertex last takes 3 − at transpositions; an odd count is undone by swapping two
            // finite vertices, so the orientation is kept.
            var face = new List<int>();
            for (int k = 0; k < 4; k++) if (k != at) face.Add(t[k]);
            if ((3 - at) % 2 == 1) face.Reverse(0, 2);
            double side = Orient(points, face[0], face[1], face[2], p);
            if (side != 0 || heights == null) return side > 0;
            return InCircle(points, heights, face[0], face[1], face[2], p) > 0;
        }

        /// <summary>det[b − a, c − a, d − a]: positive when d lies on the side of abc its normal (b − a) × (c − a) points to.</summary>
        public static double Orient(double[,] q, int a, int b, int c, int d)
        {
            double ux = q[b, 0] - q[a, 0], uy = q[b, 1] - q[a, 1], uz = q[b, 2] - q[a, 2];
            double vx = q[c, 0] - q[a, 0], vy = q[c, 1] - q[a, 1], vz = q[c, 2] - q[a, 2];
            double wx = q[d, 0] - q[a, 0], wy = q[d, 1] - q[a, 1], wz = q[d, 2] - q[a, 2];
            return ux * (vy * wz - vz * wy) + uy * (vz * wx - vx * wz) + uz * (vx * wy - vy * wx);
        }

        /// <summary>Positive when e lies inside the circumsphere of the positively oriented tetrahedron abcd.</summary>
        public static double InSphere(double[,] q, int a, int b, int c, int d, int e) => InSphere(q, null, a, b, c, d, e);

        /// <summary>As the overload, in the power distance of points lifted by <paramref name="heights"/> (null: none).</summary>
        private static double InSphere(double[,] q, double[] heights, int a, int b, int c, int d, int e)
        {
            var m = new double[4, 4];
            int[] rows = { a, b, c, d };
            for (int r = 0; r < 4; r++)
            {
                double x = q[rows[r], 0] - q[e, 0], y = q[rows[r], 1] - q[e, 1], z = q[rows[r], 2] - q[e, 2];
                m[r, 0] = x;
                m[r, 1] = y;
                m[r, 2] = z;
                m[r, 3] = x * x + y * y + z * z + (heights == null ? 0 : heights[rows[r]] - heights[e]);
            }
            // With this orientation convention the lifted determinant is negative for points inside.
            return -Determinant4(m);
        }

        /// <summary>Positive when e, in the plane of triangle abc, lies inside its power circle (heights lifted).</summary>
        private static double InCircle(double[,] q, double[] heights, int a, int b, int c, int e)
        {
            double[] A = Row(q, a), B = Row(q, b), C = Row(q, c), E = Row(q, e);
            double[] ab = Minus(B, A), ac = Minus(C, A), normal = Cross(ab, ac);
            double abLength = Math.Sqrt(Dot(ab, ab)), normalLength = Math.Sqrt(Dot(normal, normal));
            double[] u = { ab[0] / abLength, ab[1] / abLength, ab[2] / abLength };
            double[] n = { normal[0] / normalLength, normal[1] / normalLength, normal[2] / normalLength };
            double[] w = Cross(n, u);  // (u, w) right-handed about the normal: abc counter-clockwise in it
            var m = new double[3, 3];
            int[] rows = { a, b, c };
            for (int r = 0; r < 3; r++)
            {
                double[] d = Minus(Row(q, rows[r]), E);
                double x = Dot(d, u), y = Dot(d, w);
                m[r, 0] = x;
                m[r, 1] = y;
                m[r, 2] = x * x + y * y + heights[rows[r]] - heights[e];
            }
            return m[0, 0] * (m[1, 1] * m[2, 2] - m[1, 2] * m[2, 1]) - m[0, 1] * (m[1, 0] * m[2, 2] - m[1, 2] * m[2, 0]) +
                   m[0, 2] * (m[1, 0] * m[2, 1] - m[1, 1] * m[2, 0]);
        }

        private static double[] Row(double[,] q, int i) => new[] { q[i, 0], q[i, 1], q[i, 2] };
        private static double[] Minus(double[] x, double[] y) => new[] { x[0] - y[0], x[1] - y[1], x[2] - y[2] };
        private static double Dot(double[] x, double[] y) => x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
        private static double[] Cross(double[] x, double[] y) => new[] { x[1] * y[2] - x[2] * y[1], x[2] * y[0] - x[0] * y[2], x[0] * y[1] - x[1] * y[0] };

        private static double Determinant4(double[,] m)
        {
            double sum = 0;
            for (int col = 0; col < 4; col++)
            {
                var minor = new double[3, 3];
                for (int r = 1; r < 4; r++)
                {
                    int mc = 0;
                    for (int c = 0; c < 4; c++)
                    {
                        if (c == col) continue;
                        minor[r - 1, mc++] = m[r, c];
                    }
                }
                double det3 = minor[0, 0] * (minor[1, 1] * minor[2, 2] - minor[1, 2] * minor[2, 1])
                              - minor[0, 1] * (minor[1, 0] * minor[2, 2] - minor[1, 2] * minor[2, 0])
                              + minor[0, 2] * (minor[1, 0] * minor[2, 1] - minor[1, 1] * minor[2, 0]);
                sum += (col % 2 == 0 ? 1 : -1) * m[0, col] * det3;
            }
            return sum;
        }
    }
}
