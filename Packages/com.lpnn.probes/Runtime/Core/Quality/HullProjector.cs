using System;

namespace Lpnn.Probes.Core.Quality
{
    /// <summary>The nearest point of the hull surface for points outside the probes' hull (Documentation~/quality.md §1,
    /// "Outside the hull"), exact over all hull triangles: a bounding-volume hierarchy over the triangles is searched
    /// branch-and-bound, so a subtree is skipped only when its box is farther than the best triangle found, which can
    /// never skip the nearest one.
    ///
    /// Ties (Documentation~/quality.md §1 "Ties"): the nearest point of a convex hull is unique, but on a hull edge or vertex
    /// it lies on every hull triangle there, and near one (as float32 positions put many lattice points) the distances
    /// differ by less than their rounding. A point takes, among the hull triangles within a relative <see cref="Tie"/> of
    /// the smallest distance, the one owned by the lowest-index tetrahedron, then of the smallest sorted corners, with its
    /// own weights — as the Python reference (lpnn/quality/metric/hull_projection.py lowest_owner_at_ties), so the cell the
    /// insertion ranking groups it by, and its weights, do not hang on rounding.</summary>
    internal sealed class HullProjector
    {
        private const int LeafSize = 4;

        /// <summary>Hull triangles within this relative distance of the nearest one are a tie (Documentation~/quality.md §1
        /// "Ties"; Python's hull_projection.HULL_TIE).</summary>
        public const double Tie = 1e-9;

        /// <summary>By convexity, a triangle within <see cref="Tie"/> passes within half this × the distance of the nearest
        /// point; a nearest point farther than this × the distance from its triangle's edges has no tie (Python's
        /// hull_projection.TIE_REACH).</summary>
        private static readonly double TieReach = 2.0 * Math.Sqrt(2.0 * Tie + Tie * Tie);

        private readonly double[] _points;
        private readonly int[] _faces;
        private readonly int[] _owners;
        /// <summary>The triangles at each probe: <see cref="_facesAt"/>[<see cref="_facesAtStart"/>[p] ..
        /// <see cref="_facesAtStart"/>[p + 1]], ascending.</summary>
        private readonly int[] _facesAtStart;
        private readonly int[] _facesAt;
        private readonly int[] _order;
        private readonly Node[] _nodes;
        private readonly double[] _centroids;
        private int _nodeCount;

        private struct Node
        {
            public int Start, Count, Left, Right;
            public double MinX, MinY, MinZ, MaxX, MaxY, MaxZ;
        }

        /// <param name="points">Probe positions (x, y, z per probe).</param>
        /// <param name="faces">3 probe indices per hull triangle.</param>
        /// <param name="owners">The tetrahedron owning each hull triangle (for the tie rule).</param>
        public HullProjector(double[] points, int[] faces, int[] owners)
        {
            _points = points;
            _faces = faces;
            _owners = owners;
            int count = faces.Length / 3;
            _facesAtStart = new int[points.Length / 3 + 1];
            foreach (int p in faces) _facesAtStart[p + 1]++;
            for (int p = 1; p < _facesAtStart.Length; p++) _facesAtStart[p] += _facesAtStart[p - 1];
            _facesAt = new int[faces.Length];
            var filled = (int[])_facesAtStart.Clone();
            for (int k = 0; k < faces.Length; k++) _facesAt[filled[faces[k]]++] = k / 3;
            _order = new int[count];
            _centroids = new double[3 * count];
            for (int f = 0; f < count; f++)
            {
                _order[f] = f;
                for (int axis = 0; axis < 3; axis++)
                    _centroids[3 * f + axis] = (Corner(f, 0, axis) + Corner(f, 1, axis) + Corner(f, 2, axis)) / 3;
            }
            _nodes = new Node[2 * (count / (LeafSize / 2) + 1)];
            Build(0, count);
        }

        /// <summary>Scratch for <see cref="Nearest"/>'s search, one per thread that calls it (the projector itself is read
        /// only, so threads share it): depth-first with at most one pending sibling per level of a balanced tree.</summary>
        public static int[] NewStack() => new int[128];

        private double Corner(int face, int corner, int axis) => _points[3 * _faces[3 * face + corner] + axis];

        private int Build(int start, int count)
        {
            int index = _nodeCount++;
            var node = new Node { Start = start, Count = count, Left = -1, Right = -1 };
            node.MinX = node.MinY = node.MinZ = double.PositiveInfinity;
            node.MaxX = node.MaxY = node.MaxZ = double.NegativeInfinity;
            for (int k = start; k < start + count; k++)
            {
                for (int corner = 0; corner < 3; corner++)
                {
                    int f = _order[k];
                    node.MinX = Math.Min(node.MinX, Corner(f, corner, 0));
                    node.MaxX = Math.Max(node.MaxX, Corner(f, corner, 0));
                    node.MinY = Math.Min(node.MinY, Corner(f, corner, 1));
                    node.MaxY = Math.Max(node.MaxY, Corner(f, corner, 1));
                    node.MinZ = Math.Min(node.MinZ, Corner(f, corner, 2));
                    node.MaxZ = Math.Max(node.MaxZ, Corner(f, corner, 2));
                }
            }
            if (count > LeafSize)
            {
                double ex = node.MaxX - node.MinX, ey = node.MaxY - node.MinY, ez = node.MaxZ - node.MinZ;
                int axis = ex >= ey && ex >= ez ? 0 : ey >= ez ? 1 : 2;
                // Sorting by centroid keeps the build simple and deterministic; hulls have far fewer triangles than points.
                var keys = new double[count];
                var faces = new int[count];
                for (int k = 0; k < count; k++)
                {
                    faces[k] = _order[start + k];
                    keys[k] = _centroids[3 * faces[k] + axis];
                }
                Array.Sort(keys, faces);
                Array.Copy(faces, 0, _order, start, count);
                int half = count / 2;
                node.Left = Build(start, half);
                node.Right = Build(start + half, count - half);
            }
            _nodes[index] = node;
            return index;
        }

        /// <summary>The hull triangle holding the nearest hull point to (x, y, z) (the tie rule's: class text) and that point's
        /// weights on its corners. <paramref name="stack"/>: the calling thread's <see cref="NewStack"/>.</summary>
        public int Nearest(double x, double y, double z, int[] stack, out double u, out double v, out double w)
        {
            int face = NearestAny(x, y, z, stack, out u, out v, out w);
            double nearest = Math.Sqrt(DistanceSquared(face, u, v, w, x, y, z));
            if (!MayTie(face, u, v, w, nearest)) return face;
            // The tie set: the triangles at the nearest triangle's corners within a relative Tie of its distance (any
            // triangle that near the nearest point has one of those corners, unless the hull has triangles narrower than
            // TieReach × the distance); some come up more than once.
            int chosen = face;
            bool held0 = true, held1 = true, held2 = true;  // which of face's corners every tied triangle holds
            for (int corner = 0; corner < 3; corner++)
            {
                int p = _faces[3 * face + corner];
                for (int k = _facesAtStart[p]; k < _facesAtStart[p + 1]; k++)
                {
                    int f = _facesAt[k];
                    TriangleClosestPoint.Weights(x, y, z, _points, _faces[3 * f], _faces[3 * f + 1], _faces[3 * f + 2],
                        out double fu, out double fv, out double fw);
                    if (Math.Sqrt(DistanceSquared(f, fu, fv, fw, x, y, z)) > nearest * (1.0 + Tie)) continue;
                    held0 &= Holds(f, _faces[3 * face]);
                    held1 &= Holds(f, _faces[3 * face + 1]);
                    held2 &= Holds(f, _faces[3 * face + 2]);
                    if (TieOrder(f, chosen) < 0) chosen = f;
                }
            }
            int common = (held0 ? 1 : 0) + (held1 ? 1 : 0) + (held2 ? 1 : 0);
            if (common == 3) return face;  // no tie: no other triangle holds all of face's corners
            TriangleClosestPoint.Weights(x, y, z, _points, _faces[3 * chosen], _faces[3 * chosen + 1], _faces[3 * chosen + 2], out u, out v, out w);
            if (common == 0) return chosen;
            // Snapped onto the hull vertex or edge every tied triangle holds (where the exact nearest point lies), so the
            // weights do not depend on which of them is chosen; an edge's ends ordered by probe index.
            int first = -1, second = -1;
            for (int k = 0; k < 3; k++)
            {
                int corner = _faces[3 * chosen + k];
                if (!((held0 && corner == _faces[3 * face]) || (held1 && corner == _faces[3 * face + 1]) || (held2 && corner == _faces[3 * face + 2]))) continue;
                if (first < 0) first = k;
                else second = k;
            }
            var snapped = new double[3];
            if (second < 0) snapped[first] = 1;
            else
            {
                if (_faces[3 * chosen + second] < _faces[3 * chosen + first])
                {
                    int swap = first;
                    first = second;
                    second = swap;
                }
                int s = _faces[3 * chosen + first], e = _faces[3 * chosen + second];
                double ex = _points[3 * e] - _points[3 * s], ey = _points[3 * e + 1] - _points[3 * s + 1], ez = _points[3 * e + 2] - _points[3 * s + 2];
                double along = (x - _points[3 * s]) * ex + (y - _points[3 * s + 1]) * ey + (z - _points[3 * s + 2]) * ez;
                double length = ex * ex + ey * ey + ez * ez;
                double t = Math.Min(Math.Max(along / (length != 0 ? length : 1), 0.0), 1.0);
                snapped[first] = 1 - t;
                snapped[second] = t;
            }
            u = snapped[0];
            v = snapped[1];
            w = snapped[2];
            return chosen;
        }

        private bool Holds(int face, int probe) => _faces[3 * face] == probe || _faces[3 * face + 1] == probe || _faces[3 * face + 2] == probe;

        /// <summary>Whether the nearest point (weights u, v, w on <paramref name="face"/>, at <paramref name="distance"/>) lies
        /// within TieReach × the distance of one of the triangle's edge lines (weight × altitude, an upper bound of its
        /// distance to the boundary): only then may another hull triangle be as near (Python's hull_kernel.possible_ties).</summary>
        private bool MayTie(int face, double u, double v, double w, double distance)
        {
            int a = _faces[3 * face], b = _faces[3 * face + 1], c = _faces[3 * face + 2];
            double e1x = _points[3 * b] - _points[3 * a], e1y = _points[3 * b + 1] - _points[3 * a + 1], e1z = _points[3 * b + 2] - _points[3 * a + 2];
            double e2x = _points[3 * c] - _points[3 * a], e2y = _points[3 * c + 1] - _points[3 * a + 1], e2z = _points[3 * c + 2] - _points[3 * a + 2];
            double nx = e1y * e2z - e1z * e2y, ny = e1z * e2x - e1x * e2z, nz = e1x * e2y - e1y * e2x;
            double twiceArea = Math.Sqrt(nx * nx + ny * ny + nz * nz);
            double limit = TieReach * distance;
            return u * twiceArea <= limit * EdgeLength(b, c) || v * twiceArea <= limit * EdgeLength(c, a) || w * twiceArea <= limit * EdgeLength(a, b);
        }

        private double EdgeLength(int p, int q)
        {
            double dx = _points[3 * q] - _points[3 * p], dy = _points[3 * q + 1] - _points[3 * p + 1], dz = _points[3 * q + 2] - _points[3 * p + 2];
            return Math.Sqrt(dx * dx + dy * dy + dz * dz);
        }

        /// <summary>The tie rule's order of two hull triangles: lower owner first, then smaller sorted corners.</summary>
        private int TieOrder(int a, int b)
        {
            if (_owners[a] != _owners[b]) return _owners[a].CompareTo(_owners[b]);
            SortedCorners(a, out int a0, out int a1, out int a2);
            SortedCorners(b, out int b0, out int b1, out int b2);
            if (a0 != b0) return a0.CompareTo(b0);
            return a1 != b1 ? a1.CompareTo(b1) : a2.CompareTo(b2);
        }

        private void SortedCorners(int face, out int lo, out int mid, out int hi)
        {
            int a = _faces[3 * face], b = _faces[3 * face + 1], c = _faces[3 * face + 2];
            lo = Math.Min(a, Math.Min(b, c));
            hi = Math.Max(a, Math.Max(b, c));
            mid = a + b + c - lo - hi;
        }

        /// <summary>A hull triangle holding the nearest hull point (the lower triangle among exactly equal distances) and that
        /// point's weights on its corners.</summary>
        private int NearestAny(double x, double y, double z, int[] stack, out double u, out double v, out double w)
        {
            double best = double.PositiveInfinity;
            int bestFace = -1;
            u = v = w = 0;
            int depth = 0;
            stack[depth++] = 0;
            while (depth > 0)
            {
                var node = _nodes[stack[--depth]];
                if (BoxDistanceSquared(ref node, x, y, z) > best) continue;
                if (node.Left < 0)
                {
                    for (int k = node.Start; k < node.Start + node.Count; k++)
                    {
                        int f = _order[k];
                        TriangleClosestPoint.Weights(x, y, z, _points, _faces[3 * f], _faces[3 * f + 1], _faces[3 * f + 2],
                            out double fu, out double fv, out double fw);
                        double d = DistanceSquared(f, fu, fv, fw, x, y, z);
                        if (d < best || (d == best && f < bestFace))
                        {
                            best = d;
                            bestFace = f;
                            u = fu; v = fv; w = fw;
                        }
                    }
                    continue;
                }
                // Visit the nearer child first (pushed last) so the bound tightens early.
                double left = BoxDistanceSquared(ref _nodes[node.Left], x, y, z);
                double right = BoxDistanceSquared(ref _nodes[node.Right], x, y, z);
                if (left <= right)
                {
                    stack[depth++] = node.Right;
                    stack[depth++] = node.Left;
                }
                else
                {
                    stack[depth++] = node.Left;
                    stack[depth++] = node.Right;
                }
            }
            return bestFace;
        }

        private double DistanceSquared(int face, double u, double v, double w, double x, double y, double z)
        {
            double sum = 0;
            for (int axis = 0; axis < 3; axis++)
            {
                double anchor = u * Corner(face, 0, axis) + v * Corner(face, 1, axis) + w * Corner(face, 2, axis);
                double d = anchor - (axis == 0 ? x : axis == 1 ? y : z);
                sum += d * d;
            }
            return sum;
        }

        private static double BoxDistanceSquared(ref Node node, double x, double y, double z)
        {
            // Math.Max(0, Math.Max(low - v, v - high)) per axis, written out: Mono calls Math.Max (squared, a zero's sign is moot).
            double dx = node.MinX - x > x - node.MaxX ? node.MinX - x : x - node.MaxX;
            double dy = node.MinY - y > y - node.MaxY ? node.MinY - y : y - node.MaxY;
            double dz = node.MinZ - z > z - node.MaxZ ? node.MinZ - z : z - node.MaxZ;
            dx = dx > 0 ? dx : 0;
            dy = dy > 0 ? dy : 0;
            dz = dz > 0 ? dz : 0;
            return dx * dx + dy * dy + dz * dz;
        }
    }
}
