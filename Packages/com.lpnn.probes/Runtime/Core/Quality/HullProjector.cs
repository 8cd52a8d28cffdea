using System;

namespace Lpnn.Probes.Core.Quality
{
    /// <summary>The nearest point of the hull surface for points outside the probes' hull (Documentation~/quality.md §1,
    /// "Outside the hull"), exact over all hull triangles: a bounding-volume hierarchy over the triangles is searched
    /// branch-and-bound, so a subtree is skipped only when its box is farther than the best triangle found, which can
    /// never skip the nearest one. Ties go to the lower triangle (they give the same point: the nearest point of a
    /// convex hull is unique).</summary>
    internal sealed class HullProjector
    {
        private const int LeafSize = 4;

        private readonly double[] _points;
        private readonly int[] _faces;
        private readonly int[] _order;
        private readonly Node[] _nodes;
        private readonly double[] _centroids;
        private int _nodeCount;
        private readonly int[] _stack;

        private struct Node
        {
            public int Start, Count, Left, Right;
            public double MinX, MinY, MinZ, MaxX, MaxY, MaxZ;
        }

        public HullProjector(double[] points, int[] faces)
        {
            _points = points;
            _faces = faces;
            int count = faces.Length / 3;
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
            // Depth-first with at most one pending sibling per level of a balanced tree.
            _stack = new int[128];
        }

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

        /// <summary>The hull triangle holding the nearest hull point to (x, y, z) and that point's weights on its corners.</summary>
        public int Nearest(double x, double y, double z, out double u, out double v, out double w)
        {
            double best = double.PositiveInfinity;
            int bestFace = -1;
            u = v = w = 0;
            int depth = 0;
            _stack[depth++] = 0;
            while (depth > 0)
            {
                var node = _nodes[_stack[--depth]];
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
                    _stack[depth++] = node.Right;
                    _stack[depth++] = node.Left;
                }
                else
                {
                    _stack[depth++] = node.Left;
                    _stack[depth++] = node.Right;
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
            double dx = Math.Max(0, Math.Max(node.MinX - x, x - node.MaxX));
            double dy = Math.Max(0, Math.Max(node.MinY - y, y - node.MaxY));
            double dz = Math.Max(0, Math.Max(node.MinZ - z, z - node.MaxZ));
            return dx * dx + dy * dy + dz * dz;
        }
    }
}
