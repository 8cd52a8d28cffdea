using System;
using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Core.Selection
{
    /// <summary>D(p) = distance from every point to the nearest chosen point, kept exact as points are chosen one by one.
    ///
    /// Choosing c can only lower D(p) where |p − c| &lt; D(p). A static k-d tree whose nodes carry an upper bound of the
    /// D of their points finds those points without touching the rest: a node is skipped when its box is farther from c
    /// than its largest D. A uniform grid with one search radius (the largest D overall) would not do: points with tiny
    /// weights keep a large D until late in the ranking, which would make every update visit the whole volume.
    ///
    /// Distances are sqrt((dx² + dy²) + dz²) in double, the formula of Documentation~/selection.md; pruning keeps a
    /// relative margin, so it never skips a point whose computed distance would have been smaller.</summary>
    internal sealed class NearestChosenDistances
    {
        private const int LeafSize = 8;
        private const double PruneMargin = 1e-9;

        private readonly double[] _x, _y, _z;
        private readonly double[] _distance;
        private readonly int[] _order;
        private readonly Node[] _nodes;
        private int _nodeCount;

        private struct Node
        {
            public int Start, Count, Left, Right;
            public double MinX, MinY, MinZ, MaxX, MaxY, MaxZ;
            /// <summary>An upper bound of D over the node's points (exact after every visit).</summary>
            public double MaxDistance;
        }

        public NearestChosenDistances(double[] x, double[] y, double[] z)
        {
            _x = x;
            _y = y;
            _z = z;
            int count = x.Length;
            _distance = new double[count];
            for (int n = 0; n < count; n++) _distance[n] = double.PositiveInfinity;
            _order = new int[count];
            for (int n = 0; n < count; n++) _order[n] = n;
            // Halving stops below LeafSize + 1 points, so leaves hold more than LeafSize / 2: fewer than count / 4 + 1 leaves.
            _nodes = new Node[2 * (count / (LeafSize / 2) + 1)];
            if (count > 0) Build(0, count);
        }

        public double this[int point] => _distance[point];

        /// <summary>Lowers D to the distance to <paramref name="chosen"/> wherever that is smaller (D(chosen) becomes 0).</summary>
        public void Add(int chosen)
        {
            if (_x.Length > 0) Update(0, _x[chosen], _y[chosen], _z[chosen]);
        }

        private int Build(int start, int count)
        {
            int index = _nodeCount++;
            var node = new Node { Start = start, Count = count, Left = -1, Right = -1, MaxDistance = double.PositiveInfinity };
            Bounds(start, count, ref node);
            if (count > LeafSize)
            {
                double ex = node.MaxX - node.MinX, ey = node.MaxY - node.MinY, ez = node.MaxZ - node.MinZ;
                int axis = ex >= ey && ex >= ez ? 0 : ey >= ez ? 1 : 2;
                int half = count / 2;
                Statistics.SelectByKey(_order, Axis(axis), 1, 0, start, start + count - 1, start + half);
                node.Left = Build(start, half);
                node.Right = Build(start + half, count - half);
            }
            _nodes[index] = node;
            return index;
        }

        private double[] Axis(int axis) => axis == 0 ? _x : axis == 1 ? _y : _z;

        private void Bounds(int start, int count, ref Node node)
        {
            node.MinX = node.MinY = node.MinZ = double.PositiveInfinity;
            node.MaxX = node.MaxY = node.MaxZ = double.NegativeInfinity;
            for (int k = start; k < start + count; k++)
            {
                int p = _order[k];
                node.MinX = Math.Min(node.MinX, _x[p]);
                node.MaxX = Math.Max(node.MaxX, _x[p]);
                node.MinY = Math.Min(node.MinY, _y[p]);
                node.MaxY = Math.Max(node.MaxY, _y[p]);
                node.MinZ = Math.Min(node.MinZ, _z[p]);
                node.MaxZ = Math.Max(node.MaxZ, _z[p]);
            }
        }

        private void Update(int index, double cx, double cy, double cz)
        {
            var node = _nodes[index];
            double bound = node.MaxDistance;
            if (!double.IsPositiveInfinity(bound) && BoxDistanceSquared(ref node, cx, cy, cz) > bound * bound * (1 + PruneMargin)) return;
            if (node.Left < 0)
            {
                double largest = 0;
                for (int k = node.Start; k < node.Start + node.Count; k++)
                {
                    int p = _order[k];
                    double dx = _x[p] - cx, dy = _y[p] - cy, dz = _z[p] - cz;
                    double d = Math.Sqrt(dx * dx + dy * dy + dz * dz);
                    if (d < _distance[p]) _distance[p] = d;
                    if (_distance[p] > largest) largest = _distance[p];
                }
                _nodes[index].MaxDistance = largest;
                return;
            }
            Update(node.Left, cx, cy, cz);
            Update(node.Right, cx, cy, cz);
            _nodes[index].MaxDistance = Math.Max(_nodes[node.Left].MaxDistance, _nodes[node.Right].MaxDistance);
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
