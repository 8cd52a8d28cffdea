using System;
using System.Collections.Generic;
using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Core.Quality
{
    /// <summary>Checked tetrahedra over a probe set, in the evaluation points' local frame: positively oriented, flat
    /// ones dropped, each with the inverse of its edge matrix (barycentric weights in 9 multiplications), and the hull
    /// surface — the faces that belong to exactly one tetrahedron.
    ///
    /// Flat (zero-volume) tetrahedra, which a tetrahedraliser may emit for cospherical probes, contain no point and have
    /// no barycentric transform, so they are left out (as the Python reference does). Where one joined two sides that cut
    /// a quadrilateral along different diagonals, its faces are then each used by one tetrahedron and listed here among
    /// the hull faces though inside the hull (a crack, Documentation~/quality.md §1), as in Python's hull_faces: the
    /// locator never reads faces, and no point outside is nearer to an interior face than to the hull.</summary>
    internal sealed class TetrahedralMesh
    {
        /// <summary>A tetrahedron is flat when |6 × volume| is at or below this × |e1|·|e2|·|e3| (its edges from vertex 0):
        /// relative to its own edges, so it holds at any cell size and extent (an absolute 1e-14 on the unit-extent frame
        /// dropped every tetrahedron beyond ~46,000 cells along an axis). Same rule as the Python reference
        /// (lpnn/quality/metric/tet_geometry.py FLAT_RELATIVE_VOLUME; Documentation~/quality.md §1).</summary>
        public const double FlatRelativeVolume = 1e-12;

        /// <summary>Probe positions in the local frame, x, y, z per probe.</summary>
        public readonly double[] Points;
        /// <summary>4 probe indices per tetrahedron, positively oriented.</summary>
        public readonly int[] Tetrahedra;
        /// <summary>9 values per tetrahedron: rows e2×e3, e3×e1, e1×e2 over the determinant, so that
        /// (λ1, λ2, λ3) = inverse·(q − v0) and λ0 = 1 − λ1 − λ2 − λ3.</summary>
        public readonly double[] Inverse;
        /// <summary>3 probe indices per hull triangle.</summary>
        public readonly int[] HullFaces;
        /// <summary>Per hull triangle, the tetrahedron it belongs to: the cell of a point outside the hull whose nearest
        /// hull point lies on that triangle (the insertion ranking groups points by cell, quality.md §5).</summary>
        public readonly int[] HullFaceOwners;

        public int TetrahedronCount => Tetrahedra.Length / 4;
        public int HullFaceCount => HullFaces.Length / 3;

        private HashSet<TriangleKey> _hullFaceKeys;

        /// <summary>The hull faces as keys in any corner order, built on first use: a batched refinement round asks it of
        /// the same mesh for its star refills and for both meshes it derives (<see cref="StarRefills"/>,
        /// <see cref="TetrahedraAfterRemoval"/>).</summary>
        internal HashSet<TriangleKey> HullFaceKeys
        {
            get
            {
                if (_hullFaceKeys != null) return _hullFaceKeys;
                var keys = new HashSet<TriangleKey>();
                for (int f = 0; f < HullFaceCount; f++) keys.Add(new TriangleKey(HullFaces[3 * f], HullFaces[3 * f + 1], HullFaces[3 * f + 2]));
                return _hullFaceKeys = keys;
            }
        }

        private TetrahedralMesh(double[] points, int[] tetrahedra, double[] inverse, int[] hullFaces, int[] hullFaceOwners)
        {
            HullFaceOwners = hullFaceOwners;
            Points = points;
            Tetrahedra = tetrahedra;
            Inverse = inverse;
            HullFaces = hullFaces;
        }

        /// <param name="points">Probe positions in the local frame (x, y, z per probe).</param>
        /// <param name="tetrahedra">4 indices into the probes per tetrahedron.</param>
        public static TetrahedralMesh Build(double[] points, int[] tetrahedra)
        {
            if (tetrahedra == null) throw new ArgumentNullException(nameof(tetrahedra));
            int probes = points.Length / 3;
            if (tetrahedra.Length == 0 || tetrahedra.Length % 4 != 0)
                throw new PlacementErrorException("tetrahedra come as 4 probe indices each; got " + InvariantFormat.Count(tetrahedra.Length) +
                                                  " indices" + (tetrahedra.Length == 0 ? " (none: the probes could not be tetrahedralised)" : ""));
            CheckIndices(tetrahedra, probes);

            // Arrays filled in place rather than Lists (Mono does not inline List.Add): trimmed when flat ones were dropped.
            var kept = new int[tetrahedra.Length];
            var inverse = new double[tetrahedra.Length / 4 * 9];
            int count = 0;
            for (int t = 0; t < tetrahedra.Length; t += 4)
                if (AddOriented(points, tetrahedra[t], tetrahedra[t + 1], tetrahedra[t + 2], tetrahedra[t + 3], kept, inverse, count)) count++;
            if (count == 0)
                throw new PlacementErrorException("all " + InvariantFormat.Count(tetrahedra.Length / 4) + " tetrahedra are flat (no volume): the " + probes +
                                                  " probes lie in one plane; add a probe off that plane, e.g. make the volume two cells deep");
            if (4 * count < kept.Length)
            {
                Array.Resize(ref kept, 4 * count);
                Array.Resize(ref inverse, 9 * count);
            }
            int[] hull = HullOf(kept, out int[] owners);
            return new TetrahedralMesh(points, kept, inverse, hull, owners);
        }

        /// <summary>Whether <paramref name="other"/> (over the same probes) has the same tetrahedra, each as a set of four
        /// probes: whatever their order and their vertices' order (a derived mesh against a fresh tetrahedralisation).</summary>
        internal bool HasTheTetrahedraOf(TetrahedralMesh other)
        {
            if (other.Tetrahedra.Length != Tetrahedra.Length) return false;
            int[] mine = TetrahedronNumbering.Numbered(Tetrahedra, null), theirs = TetrahedronNumbering.Numbered(other.Tetrahedra, null);
            for (int k = 0; k < mine.Length; k++)
                if (mine[k] != theirs[k]) return false;
            return true;
        }

        private static void CheckIndices(int[] tetrahedra, int probes)
        {
            for (int t = 0; t < tetrahedra.Length; t += 4)
            {
                for (int k = 0; k < 4; k++)
                {
                    int v = tetrahedra[t + k];
                    if ((uint)v >= (uint)probes)
                        throw new PlacementErrorException("tetrahedron " + t / 4 + " references probe " + v + ", but there are only " + probes +
                                                          " probes (indices 0.." + (probes - 1) + ")");
                    for (int j = 0; j < k; j++)
                        if (tetrahedra[t + j] == v)
                            throw new PlacementErrorException("tetrahedron " + t / 4 + " uses probe " + v + " twice");
                }
            }
        }

        /// <summary>Writes tetrahedron (a, b, c, d), positively oriented, as the <paramref name="index"/>-th of
        /// <paramref name="kept"/> with its inverse; false (nothing written) when it is flat.</summary>
        private static bool AddOriented(double[] p, int a, int b, int c, int d, int[] kept, double[] inverse, int index)
        {
            double e1x = p[3 * b] - p[3 * a], e1y = p[3 * b + 1] - p[3 * a + 1], e1z = p[3 * b + 2] - p[3 * a + 2];
            double e2x = p[3 * c] - p[3 * a], e2y = p[3 * c + 1] - p[3 * a + 1], e2z = p[3 * c + 2] - p[3 * a + 2];
            double e3x = p[3 * d] - p[3 * a], e3y = p[3 * d + 1] - p[3 * a + 1], e3z = p[3 * d + 2] - p[3 * a + 2];
            double det = e1x * (e2y * e3z - e2z * e3y) + e1y * (e2z * e3x - e2x * e3z) + e1z * (e2x * e3y - e2y * e3x);
            if (IsFlat(det, e1x, e1y, e1z, e2x, e2y, e2z, e3x, e3y, e3z)) return false;
            if (det < 0)
            {
                // Swapping the last two vertices (and edges) flips the orientation.
                int swap = c;
                c = d;
                d = swap;
                double tx = e2x, ty = e2y, tz = e2z;
                e2x = e3x; e2y = e3y; e2z = e3z;
                e3x = tx; e3y = ty; e3z = tz;
                det = -det;
            }
            kept[4 * index] = a;
            kept[4 * index + 1] = b;
            kept[4 * index + 2] = c;
            kept[4 * index + 3] = d;
            SetRow(inverse, 9 * index, e2x, e2y, e2z, e3x, e3y, e3z, det);
            SetRow(inverse, 9 * index + 3, e3x, e3y, e3z, e1x, e1y, e1z, det);
            SetRow(inverse, 9 * index + 6, e1x, e1y, e1z, e2x, e2y, e2z, det);
            return true;
        }

        /// <summary>6 × the signed volume of the tetrahedron (a, b, c, d) of <paramref name="p"/> (x, y, z per index), and
        /// whether it is flat by <see cref="FlatRelativeVolume"/>: the rule <see cref="Build"/> drops tetrahedra by, for
        /// tetrahedra made outside a tetrahedralisation (the batched refinement's star refills).</summary>
        internal static double Volume6(double[] p, int a, int b, int c, int d, out bool flat)
        {
            double e1x = p[3 * b] - p[3 * a], e1y = p[3 * b + 1] - p[3 * a + 1], e1z = p[3 * b + 2] - p[3 * a + 2];
            double e2x = p[3 * c] - p[3 * a], e2y = p[3 * c + 1] - p[3 * a + 1], e2z = p[3 * c + 2] - p[3 * a + 2];
            double e3x = p[3 * d] - p[3 * a], e3y = p[3 * d + 1] - p[3 * a + 1], e3z = p[3 * d + 2] - p[3 * a + 2];
            double det = e1x * (e2y * e3z - e2z * e3y) + e1y * (e2z * e3x - e2x * e3z) + e1z * (e2x * e3y - e2y * e3x);
            flat = IsFlat(det, e1x, e1y, e1z, e2x, e2y, e2z, e3x, e3y, e3z);
            return det;
        }

        private static bool IsFlat(double det, double e1x, double e1y, double e1z, double e2x, double e2y, double e2z,
            double e3x, double e3y, double e3z)
        {
            double edgeProduct = Math.Sqrt((e1x * e1x + e1y * e1y + e1z * e1z) * (e2x * e2x + e2y * e2y + e2z * e2z) *
                                           (e3x * e3x + e3y * e3y + e3z * e3z));
            return !(Math.Abs(det) > FlatRelativeVolume * edgeProduct);
        }

        /// <summary>Writes (u × v) / det at <paramref name="at"/>.</summary>
        private static void SetRow(double[] inverse, int at, double ux, double uy, double uz, double vx, double vy, double vz, double det)
        {
            inverse[at] = (uy * vz - uz * vy) / det;
            inverse[at + 1] = (uz * vx - ux * vz) / det;
            inverse[at + 2] = (ux * vy - uy * vx) / det;
        }

        /// <summary>The faces used by exactly one tetrahedron, in ascending order of their sorted corners; a face used by
        /// three or more means the input is not a tetrahedralisation. The faces are sorted as packed keys
        /// (<see cref="KeySort"/>), not compared one pair at a time (Mono's Array.Sort of structs calls a delegate per
        /// comparison): the same order, so the same hull.</summary>
        private static int[] HullOf(int[] tets, out int[] owners)
        {
            int faceCount = tets.Length;  // 4 per tetrahedron: face 4t + k leaves out corner k of tetrahedron t
            var corners = new int[3 * faceCount];  // ascending per face
            int largest = 0;
            for (int t = 0; t < tets.Length; t += 4)
            {
                int a = tets[t], b = tets[t + 1], c = tets[t + 2], d = tets[t + 3];
                SetFace(corners, t, b, c, d);
                SetFace(corners, t + 1, a, c, d);
                SetFace(corners, t + 2, a, b, d);
                SetFace(corners, t + 3, a, b, c);
                largest = Math.Max(largest, Math.Max(Math.Max(a, b), Math.Max(c, d)));
            }
            var order = new int[faceCount];
            for (int f = 0; f < faceCount; f++) order[f] = f;
            var keys = new long[faceCount];
            int bits = 1;
            while (bits < 31 && (largest >> bits) != 0) bits++;
            if (3 * bits <= 63)
            {
                for (int f = 0; f < faceCount; f++)
                    keys[f] = ((long)corners[3 * f] << (2 * bits)) | ((long)corners[3 * f + 1] << bits) | (uint)corners[3 * f + 2];
                KeySort.Sort(keys, order, faceCount);
            }
            else
            {
                // Too many probes to pack three corners: by the last two, then (stable) by the first.
                for (int f = 0; f < faceCount; f++) keys[f] = ((long)corners[3 * f + 1] << 32) | (uint)corners[3 * f + 2];
                KeySort.Sort(keys, order, faceCount);
                for (int i = 0; i < faceCount; i++) keys[i] = corners[3 * order[i]];
                KeySort.Sort(keys, order, faceCount);
            }
            var hull = new List<int>();
            var owner = new List<int>();
            for (int start = 0; start < faceCount;)
            {
                int first = 3 * order[start];
                int end = start + 1;
                while (end < faceCount && SameFace(corners, first, 3 * order[end])) end++;
                int uses = end - start;
                if (uses > 2)
                    throw new PlacementErrorException("the triangle of probes " + corners[first] + ", " + corners[first + 1] + ", " + corners[first + 2] + " belongs to " + uses +
                                                      " tetrahedra; the tetrahedra do not form a valid tetrahedralisation (overlapping or repeated tetrahedra)");
                if (uses == 1)
                {
                    hull.Add(corners[first]);
                    hull.Add(corners[first + 1]);
                    hull.Add(corners[first + 2]);
                    owner.Add(order[start] / 4);
                }
                start = end;
            }
            if (hull.Count == 0)
                throw new PlacementErrorException("the tetrahedra have no boundary (every triangle is shared by two of them): the same " +
                                                  "tetrahedra are listed twice; pass each tetrahedron once");
            owners = owner.ToArray();
            return hull.ToArray();
        }

        /// <summary>Face <paramref name="face"/>'s corners, ascending, at 3 × face (as <see cref="TriangleKey"/> orders them).</summary>
        private static void SetFace(int[] corners, int face, int x, int y, int z)
        {
            var key = new TriangleKey(x, y, z);
            corners[3 * face] = key.A;
            corners[3 * face + 1] = key.B;
            corners[3 * face + 2] = key.C;
        }

        private static bool SameFace(int[] corners, int i, int j) =>
            corners[i] == corners[j] && corners[i + 1] == corners[j + 1] && corners[i + 2] == corners[j + 2];
    }
}
