namespace Lpnn.Probes.Core.Selection
{
    /// <summary>A binary max-heap of (value, point) pairs: larger value first, equal values by lower point index, the
    /// tie rule of every ranking in Documentation~/selection.md.</summary>
    internal sealed class RankHeap
    {
        private double[] _values;
        private int[] _points;

        public int Count { get; private set; }

        public RankHeap(int capacity)
        {
            _values = new double[System.Math.Max(1, capacity)];
            _points = new int[System.Math.Max(1, capacity)];
        }

        public double TopValue => _values[0];
        public int TopPoint => _points[0];

        public void Push(double value, int point)
        {
            if (Count == _values.Length)
            {
                System.Array.Resize(ref _values, 2 * Count);
                System.Array.Resize(ref _points, 2 * Count);
            }
            int at = Count++;
            while (at > 0)
            {
                int parent = (at - 1) / 2;
                if (!Before(value, point, _values[parent], _points[parent])) break;
                _values[at] = _values[parent];
                _points[at] = _points[parent];
                at = parent;
            }
            _values[at] = value;
            _points[at] = point;
        }

        public void Pop()
        {
            Count--;
            if (Count == 0) return;
            double value = _values[Count];
            int point = _points[Count];
            int at = 0;
            while (true)
            {
                int child = 2 * at + 1;
                if (child >= Count) break;
                if (child + 1 < Count && Before(_values[child + 1], _points[child + 1], _values[child], _points[child])) child++;
                if (!Before(_values[child], _points[child], value, point)) break;
                _values[at] = _values[child];
                _points[at] = _points[child];
                at = child;
            }
            _values[at] = value;
            _points[at] = point;
        }

        private static bool Before(double value, int point, double otherValue, int otherPoint) =>
            value > otherValue || (value == otherValue && point < otherPoint);
    }
}
