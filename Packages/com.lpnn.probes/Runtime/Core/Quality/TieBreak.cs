using System;
using System.Collections.Generic;
using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Core.Quality
{
    /// <summary>The tie-breaking heights of the tetrahedralisation the quality metric assumes (Documentation~/quality.md
    /// §1): a lattice is cospherical, so its Delaunay tetrahedralisation is not unique; Python lifts each point to
    /// |x|² + h(x), with h a deterministic hash of the point's world position scaled to 10⁻⁵ of the squared median
    /// nearest-neighbour spacing, which makes the triangulation unique and the same for every subset. The batched
    /// refinement's star refills (<see cref="HoleWrap"/>) must choose among cospherical points as that tetrahedralisation
    /// does, so they lift with the same heights: port of lpnn/quality/metric/triangulation.py (position_hash,
    /// Frame.for_points' spacing, Frame.tie_heights), in the same local frame as <see cref="ReferenceLighting.Local"/>.
    /// Unity's native tetrahedraliser breaks ties its own way; the refills are then still a Delaunay tetrahedralisation,
    /// only not necessarily Unity's (as the rest of the refinement already assumes, RefinedSelection's final check).</summary>
    internal static class TieBreak
    {
        /// <summary>The perturbation amplitude as a fraction of the squared spacing (triangulation.py TIE_BREAK_FRACTION).</summary>
        public const double Fraction = 1e-5;

        /// <summary>Per point of <paramref name="reference"/>, its height in local units squared.</summary>
        public static double[] Heights(ReferenceLighting reference)
        {
            double amplitude = Fraction * Square(MedianSpacing(reference.Local));
            var heights = new double[reference.Count];
            for (int p = 0; p < heights.Length; p++)
            {
                var position = reference.GetPosition(p);
                heights[p] = amplitude * PositionHash(position.X, position.Y, position.Z);
            }
            return heights;
        }

        /// <summary>A value in [0, 1) that depends only on the float64 bits of the position (triangulation.py
        /// position_hash: splitmix64's finaliser chained over x, y, z).</summary>
        public static double PositionHash(double x, double y, double z)
        {
            ulong key = Mix((ulong)BitConverter.DoubleToInt64Bits(x) + 0x9E3779B97F4A7C15UL);
            key = Mix(key ^ (ulong)BitConverter.DoubleToInt64Bits(y));
            key = Mix(key ^ (ulong)BitConverter.DoubleToInt64Bits(z));
            return (key >> 11) / 9007199254740992.0;  // 2^53
        }

        private static ulong Mix(ulong x)
        {
            unchecked
            {
                x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9UL;
                x = (x ^ (x >> 27)) * 0x94D049BB133111EBUL;
                return x ^ (x >> 31);
            }
        }

        private static double Square(double x) => x * x;

        /// <summary>The median of the positive nearest-neighbour distances (1 when there are none), as Frame.for_points
        /// takes it: each point's nearest other point, a duplicate's 0 left out.</summary>
        internal static double MedianSpacing(double[] local)
        {
            int count = local.Length / 3;
            if (count < 2) return 1.0;
            var tree = new NearestNeighbours(local);
            var positive = new List<double>(count);
            for (int p = 0; p < count; p++)
            {
                double d = tree.NearestOther(p);
                if (d > 0) positive.Add(d);
            }
            return positive.Count == 0 ? 1.0 : Statistics.Median(positive);
        }

        /// <summary>A static k-d tree for each point's distance to its nearest other point.</summary>
        private sealed class NearestNeighbours
        {
            private const int LeafSize = 8;
            private readonly double[] _p;
            private readonly int[] _order;
            private readonly List<Node> _nodes = new List<Node>();

            private struct Node
            {
                public int Start, Count, Left, Right;
                public double MinX, MinY, MinZ, MaxX, MaxY, MaxZ;
            }

            public NearestNeighbours(double[] local)
            {
                _p = local;
                _order = new int[local.Length / 3];
                for (int n = 0; n < _order.Length; n++) _order[n] = n;
                Build(0, _order.Length);
            }

            private int Build(int start, int count)
            {
                int index = _nodes.Count;
                _nodes.Add(default(Node));
                var node = new Node { Start = start, Count = count, Left = -1, Right = -1 };
                node.MinX = node.MinY = node.MinZ = double.PositiveInfinity;
                node.MaxX = node.MaxY = node.MaxZ = double.NegativeInfinity;
                for (int k = start; k < start + count; k++)
                {
                    int q = 3 * _order[k];
                    node.MinX = Math.Min(node.MinX, _p[q]);
                    node.MaxX = Math.Max(node.MaxX, _p[q]);
                    node.MinY = Math.Min(node.MinY, _p[q + 1]);
                    node.MaxY = Math.Max(node.MaxY, _p[q + 1]);
                    node.MinZ = Math.Min(node.MinZ, _p[q + 2]);
                    node.MaxZ = Math.Max(node.MaxZ, _p[q + 2]);
                }
                if (count > LeafSize)
                {
                    double ex = node.MaxX - node.MinX, ey = node.MaxY - node.MinY, ez = node.MaxZ - node.MinZ;
                    int axis = ex >= ey && ex >= ez ? 0 : ey >= ez ? 1 : 2;
                    int half = count / 2;
                    Statistics.SelectByKey(_order, _p, 3, axis, start, start + count - 1, start + half);
                    node.Left = Build(start, half);
                    node.Right = Build(start + half, count - half);
                }
                _nodes[index] = node;
                return index;
            }

            /// <summary>The distance from point <paramref name="p"/> to the nearest other point (0 for a duplicate).</summary>
            public double NearestOther(int p)
            {
                double best = double.PositiveInfinity;
                Search(0, p, _p[3 * p], _p[3 * p + 1], _p[3 * p + 2], ref best);
                return Math.Sqrt(best);
            }

            private void Search(int index, int p, double x, double y, double z, ref double best)
            {
                var node = _nodes[index];
                double dx = Math.Max(0, Math.Max(node.MinX - x, x - node.MaxX));
                double dy = Math.Max(0, Math.Max(node.MinY - y, y - node.MaxY));
                double dz = Math.Max(0, Math.Max(node.MinZ - z, z - node.MaxZ));
                if (dx * dx + dy * dy + dz * dz > best) return;
                if (node.Left < 0)
                {
                    for (int k = node.Start; k < node.Start + node.Count; k++)
                    {
                        int q = _order[k];
                        if (q == p) continue;
                        double ux = _p[3 * q] - x, uy = _p[3 * q + 1] - y, uz = _p[3 * q + 2] - z;
                        double d = ux * ux + uy * uy + uz * uz;
                        if (d < best) best = d;
                    }
                    return;
                }
                // The child on the point's side first: its nearest point prunes most of the other.
                var left = _nodes[node.Left];
                bool inLeft = x >= left.MinX && x <= left.MaxX && y >= left.MinY && y <= left.MaxY && z >= left.MinZ && z <= left.MaxZ;
                Search(inLeft ? node.Left : node.Right, p, x, y, z, ref best);
                Search(inLeft ? node.Right : node.Left, p, x, y, z, ref best);
            }
        }
    }
}
