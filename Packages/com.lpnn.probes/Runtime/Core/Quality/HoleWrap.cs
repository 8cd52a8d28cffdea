using System;

namespace Lpnn.Probes.Core.Quality
{
    /// <summary>The tetrahedra that refill the hole a probe leaves when it is not a vertex of the hull, by gift wrapping
    /// (Documentation~/quality.md §5.3). Port of lpnn/quality/placement/decimation/hole_wrap.py (_wrap_one), the same
    /// steps and limits, so that both languages refill a star with the same tetrahedra in the same vertex order.
    ///
    /// When probe v goes, its star is refilled by the regular (tie-broken Delaunay, <see cref="TieBreak"/>) tetrahedra of
    /// its link that lie in the star. Each rests on a face of the hole's boundary (the star's faces opposite v) or of
    /// another hole tetrahedron; on a face (a, b, c) it is completed by the link point p on the inner side that the lifted
    /// hyperplane through a, b, c meets first as it tilts into that side, the smallest (h(p) − L(p)) / dist(p), with h the
    /// lifted height, L the affine function equal to h at a, b, c whose gradient lies in their plane, and dist(p) the
    /// (scaled) distance of p from that plane. In exact arithmetic this gives the tetrahedra of the lower hull of the lifted
    /// link, i.e. what a tetrahedralisation of the remaining probes puts there (the triangulation is unique), without one.
    /// A hole fails (null: the caller refills it another way) when a face has no link point on its inner side, a face is
    /// shared by three tetrahedra, or it does not close within the size limits; the caller also checks its volume.
    ///
    /// Heights are taken relative to v (|x − v|² + tie height: the same lifting up to an affine function), so competing
    /// keys keep their precision: on grids they differ only by the tie heights, ~10⁻⁵ of the squared spacing.</summary>
    internal static class HoleWrap
    {
        /// <summary>|dist| ≤ this × |n|^1.5 (a spacing³ scale): the point lies on the face's plane (hole_wrap.py ON_PLANE).</summary>
        public const double OnPlane = 1e-9;
        /// <summary>Larger links are not wrapped (hole_wrap.py MAX_LINK).</summary>
        public const int MaxLink = 96;
        /// <summary>Faces a hole may register (a closed hole of d points has fewer than 4d).</summary>
        public const int MaxFaces = 8 * MaxLink;

        private const int DegenerateFace = -2;

        /// <summary>The tetrahedra (global ids, 4 each, not oriented) that refill probe <paramref name="v"/>'s hole, or
        /// null when wrapping failed; at most twice as many as the star has.</summary>
        /// <param name="local">Every point's local position (x, y, z per point).</param>
        /// <param name="tie">Every point's tie height (<see cref="TieBreak.Heights"/>).</param>
        /// <param name="star">v's star: 4 global ids per tetrahedron, each holding v.</param>
        /// <param name="onHull">v lies on the hull's surface (not a vertex of it), so a face the wrapping creates may have
        /// nothing on its far side (it lies on the hull).</param>
        public static int[] Wrap(double[] local, double[] tie, int v, int[] star, bool onHull)
        {
            int starCount = star.Length / 4;
            var link = new int[MaxLink];
            int d = CollectLink(star, v, link);
            if (d <= 0) return null;
            var x = new double[3 * d];
            var h = new double[d];
            for (int i = 0; i < d; i++)
            {
                for (int k = 0; k < 3; k++) x[3 * i + k] = local[3 * link[i] + k] - local[3 * v + k];
                h[i] = x[3 * i] * x[3 * i] + x[3 * i + 1] * x[3 * i + 1] + x[3 * i + 2] * x[3 * i + 2] + tie[link[i]];
            }

            // Boundary faces (link numbering), v on the positive side; each registered once (the star's side).
            var faces = new int[3 * MaxFaces];
            var seen = new int[MaxFaces];
            var queue = new int[3 * MaxFaces];
            int count = 0, pending = 0;
            var tri = new int[3];
            for (int t = 0; t < starCount; t++)
            {
                int m = 0;
                for (int j = 0; j < 4; j++)
                {
                    int u = star[4 * t + j];
                    if (u == v) continue;
                    for (int i = 0; i < d; i++)
                        if (link[i] == u) tri[m] = i;
                    m++;
                }
                int a = tri[0], b = tri[1], c = tri[2];
                if (OrientAtOrigin(x, a, b, c) < 0.0) { int s = b; b = c; c = s; }  // v must be on the positive side
                int index = Register(faces, seen, ref count, a, b, c);
                if (index < 0 || seen[index] > 1) return null;  // a repeated boundary face: not a proper star
                queue[3 * pending] = a;
                queue[3 * pending + 1] = b;
                queue[3 * pending + 2] = c;
                pending++;
            }
            var made = new int[4 * 2 * starCount];
            int madeCount = 0, head = 0;
            while (head < pending)
            {
                int a = queue[3 * head], b = queue[3 * head + 1], c = queue[3 * head + 2];
                head++;
                int here = FindFace(faces, count, new TriangleKey(a, b, c));
                if (seen[here] >= 2) continue;  // closed meanwhile
                int best = LowestApex(x, h, d, a, b, c);
                if (best == DegenerateFace) return null;
                if (best < 0 && onHull && head > starCount)
                {
                    seen[here] = 2;  // a face of the hull: nothing on its far side
                    continue;
                }
                if (best < 0 || madeCount == 2 * starCount) return null;
                made[4 * madeCount] = link[a];
                made[4 * madeCount + 1] = link[b];
                made[4 * madeCount + 2] = link[c];
                made[4 * madeCount + 3] = link[best];
                madeCount++;
                seen[here]++;
                // The other three faces; the inner side of each is away from the vertex it leaves out.
                for (int f = 0; f < 3; f++)
                {
                    int p0, p1, p2, away;
                    if (f == 0) { p0 = a; p1 = b; p2 = best; away = c; }
                    else if (f == 1) { p0 = b; p1 = c; p2 = best; away = a; }
                    else { p0 = c; p1 = a; p2 = best; away = b; }
                    int index = Register(faces, seen, ref count, p0, p1, p2);
                    if (index < 0 || seen[index] > 2) return null;
                    if (seen[index] != 1) continue;
                    if (pending == MaxFaces) return null;
                    if (Orient(x, p0, p1, p2, away) > 0.0) { int s = p1; p1 = p2; p2 = s; }
                    queue[3 * pending] = p0;
                    queue[3 * pending + 1] = p1;
                    queue[3 * pending + 2] = p2;
                    pending++;
                }
            }
            for (int i = 0; i < count; i++)
                if (seen[i] != 2) return null;
            if (madeCount == 0) return null;
            var result = new int[4 * madeCount];
            Array.Copy(made, result, result.Length);
            return result;
        }

        /// <summary>The distinct vertices of the star other than v, in order of appearance; -1 when more than
        /// <see cref="MaxLink"/>.</summary>
        private static int CollectLink(int[] star, int v, int[] link)
        {
            int d = 0;
            foreach (int u in star)
            {
                if (u == v) continue;
                bool known = false;
                for (int i = 0; i < d && !known; i++) known = link[i] == u;
                if (known) continue;
                if (d == link.Length) return -1;
                link[d++] = u;
            }
            return d;
        }

        /// <summary>Signed 6 × volume of (x[a], x[b], x[c], q).</summary>
        private static double Orient(double[] x, int a, int b, int c, int q) =>
            OrientTo(x, a, b, c, x[3 * q], x[3 * q + 1], x[3 * q + 2]);

        /// <summary>Signed 6 × volume of (x[a], x[b], x[c], v), v the origin of the link's coordinates.</summary>
        private static double OrientAtOrigin(double[] x, int a, int b, int c) => OrientTo(x, a, b, c, 0, 0, 0);

        private static double OrientTo(double[] x, int a, int b, int c, double qx, double qy, double qz)
        {
            double e1x = x[3 * b] - x[3 * a], e1y = x[3 * b + 1] - x[3 * a + 1], e1z = x[3 * b + 2] - x[3 * a + 2];
            double e2x = x[3 * c] - x[3 * a], e2y = x[3 * c + 1] - x[3 * a + 1], e2z = x[3 * c + 2] - x[3 * a + 2];
            double e3x = qx - x[3 * a], e3y = qy - x[3 * a + 1], e3z = qz - x[3 * a + 2];
            return (e1y * e2z - e1z * e2y) * e3x + (e1z * e2x - e1x * e2z) * e3y + (e1x * e2y - e1y * e2x) * e3z;
        }

        /// <summary>Index of the registered face with vertices <paramref name="key"/>, or -1.</summary>
        private static int FindFace(int[] faces, int count, TriangleKey key)
        {
            for (int i = 0; i < count; i++)
                if (faces[3 * i] == key.A && faces[3 * i + 1] == key.B && faces[3 * i + 2] == key.C) return i;
            return -1;
        }

        /// <summary>Counts one more tetrahedron on face {a, b, c}: its index, or -1 when there is no room for a new face.</summary>
        private static int Register(int[] faces, int[] seen, ref int count, int a, int b, int c)
        {
            var key = new TriangleKey(a, b, c);
            int found = FindFace(faces, count, key);
            if (found >= 0)
            {
                seen[found]++;
                return found;
            }
            if (count == seen.Length) return -1;
            faces[3 * count] = key.A;
            faces[3 * count + 1] = key.B;
            faces[3 * count + 2] = key.C;
            seen[count] = 1;
            return count++;
        }

        /// <summary>The link point on the positive side of face (a, b, c) whose lifted point lies lowest above the face's
        /// lifted plane (the regular-triangulation apex); -1 when none, <see cref="DegenerateFace"/> for a flat face.</summary>
        private static int LowestApex(double[] x, double[] h, int d, int a, int b, int c)
        {
            double e1x = x[3 * b] - x[3 * a], e1y = x[3 * b + 1] - x[3 * a + 1], e1z = x[3 * b + 2] - x[3 * a + 2];
            double e2x = x[3 * c] - x[3 * a], e2y = x[3 * c + 1] - x[3 * a + 1], e2z = x[3 * c + 2] - x[3 * a + 2];
            double n0 = e1y * e2z - e1z * e2y, n1 = e1z * e2x - e1x * e2z, n2 = e1x * e2y - e1y * e2x;
            double g11 = e1x * e1x + e1y * e1y + e1z * e1z;
            double g12 = e1x * e2x + e1y * e2y + e1z * e2z;
            double g22 = e2x * e2x + e2y * e2y + e2z * e2z;
            double gram = g11 * g22 - g12 * g12;
            if (!(gram > 0.0)) return DegenerateFace;
            double db = h[b] - h[a], dc = h[c] - h[a];
            double alpha = (db * g22 - dc * g12) / gram, beta = (dc * g11 - db * g12) / gram;
            double floor = OnPlane * Math.Pow(gram, 0.75);
            int best = -1;
            double bestKey = double.PositiveInfinity;
            for (int p = 0; p < d; p++)
            {
                if (p == a || p == b || p == c) continue;
                double e30 = x[3 * p] - x[3 * a], e31 = x[3 * p + 1] - x[3 * a + 1], e32 = x[3 * p + 2] - x[3 * a + 2];
                double distance = n0 * e30 + n1 * e31 + n2 * e32;
                if (distance <= floor) continue;
                double rise = h[p] - h[a] - alpha * (e1x * e30 + e1y * e31 + e1z * e32) - beta * (e2x * e30 + e2y * e31 + e2z * e32);
                double key = rise / distance;
                if (key < bestKey)
                {
                    best = p;
                    bestKey = key;
                }
            }
            return best;
        }
    }
}
