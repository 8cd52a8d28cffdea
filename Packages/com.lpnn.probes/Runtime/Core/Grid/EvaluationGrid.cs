using System;
using System.Collections.Generic;
using System.Numerics;
using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Core.Grid
{
    /// <summary>The evaluation points of a volume, in grid order (k, then j, then i). Point index = position in
    /// that order; every per-point array (SH, features, labels, scores) is indexed by it.</summary>
    public sealed class EvaluationGrid
    {
        private readonly int[] _ids;
        private readonly float[] _positions;
        private readonly GridBox[] _boxes;
        private Dictionary<LatticeId, int> _indexById;

        public double CellSize { get; }
        public int Count { get; }

        /// <summary>The boxes the grid was built from (empty for grids rebuilt from stored ids).</summary>
        public IReadOnlyList<GridBox> Boxes => _boxes;

        internal EvaluationGrid(double cellSize, int[] ids, GridBox[] boxes)
        {
            CellSize = cellSize;
            _ids = ids;
            _boxes = boxes;
            Count = ids.Length / 3;
            _positions = new float[ids.Length];
            for (int c = 0; c < ids.Length; c++) _positions[c] = (float)(cellSize * ids[c]);
        }

        /// <summary>Rebuilds a grid from stored ids (a capture): checks they are unique and in grid order.</summary>
        public static EvaluationGrid FromIds(double cellSize, IReadOnlyList<LatticeId> ids)
        {
            if (!(cellSize > 0) || double.IsInfinity(cellSize))
                throw new GridException("cell size " + InvariantFormat.Number(cellSize) + " must be a finite number greater than 0");
            if (ids == null || ids.Count == 0) throw new GridException("a grid needs at least one point");
            var flat = new int[ids.Count * 3];
            for (int n = 0; n < ids.Count; n++)
            {
                var id = ids[n];
                if (Math.Abs((long)id.I) > LatticeId.MaxCoordinate || Math.Abs((long)id.J) > LatticeId.MaxCoordinate ||
                    Math.Abs((long)id.K) > LatticeId.MaxCoordinate)
                    throw new GridException("point " + n + " has id " + id + " beyond ±2^30");
                if (n > 0 && ids[n - 1].CompareTo(id) >= 0)
                    throw new GridException("point " + n + " (id " + id + ") is not after point " + (n - 1) + " (id " + ids[n - 1] +
                                            ") in grid order (k, then j, then i, strictly increasing)");
                flat[3 * n] = id.I;
                flat[3 * n + 1] = id.J;
                flat[3 * n + 2] = id.K;
            }
            return new EvaluationGrid(cellSize, flat, new GridBox[0]);
        }

        /// <summary>The grid restricted to the points where <paramref name="keep"/> is true (order kept):
        /// e.g. without the points found inside walls.</summary>
        public EvaluationGrid Subset(IReadOnlyList<bool> keep)
        {
            if (keep == null || keep.Count != Count)
                throw new ArgumentException("keep mask needs one entry per point (" + Count + ")", nameof(keep));
            int kept = 0;
            for (int n = 0; n < Count; n++) if (keep[n]) kept++;
            if (kept == 0) throw new GridException("no evaluation point is left after filtering all " + Count + " points");
            var ids = new int[kept * 3];
            int m = 0;
            for (int n = 0; n < Count; n++)
            {
                if (!keep[n]) continue;
                Array.Copy(_ids, 3 * n, ids, 3 * m, 3);
                m++;
            }
            return new EvaluationGrid(CellSize, ids, _boxes);
        }

        public LatticeId GetId(int index)
        {
            CheckIndex(index);
            return new LatticeId(_ids[3 * index], _ids[3 * index + 1], _ids[3 * index + 2]);
        }

        /// <summary>World position (cell size × id, formed in double, stored as float).</summary>
        public Vector3 GetPosition(int index)
        {
            CheckIndex(index);
            return new Vector3(_positions[3 * index], _positions[3 * index + 1], _positions[3 * index + 2]);
        }

        /// <summary>Copies all positions as x,y,z triples (3 × Count floats).</summary>
        public float[] CopyPositions() => (float[])_positions.Clone();

        /// <summary>Copies all ids as i,j,k triples (3 × Count ints).</summary>
        public int[] CopyIds() => (int[])_ids.Clone();

        /// <summary>Index of the point with this id, or −1 when it is not in the grid.</summary>
        public int IndexOf(LatticeId id)
        {
            if (_indexById == null) BuildIndex();
            return _indexById.TryGetValue(id, out int index) ? index : -1;
        }

        /// <summary>Index of the point <paramref name="offset"/> cells from point <paramref name="index"/> along
        /// <paramref name="axis"/> (0 = x, 1 = y, 2 = z), or −1 when that point is not in the grid.</summary>
        public int Neighbour(int index, int axis, int offset) => IndexOf(GetId(index).Offset(axis, offset));

        private void BuildIndex()
        {
            var map = new Dictionary<LatticeId, int>(Count);
            for (int n = 0; n < Count; n++) map[new LatticeId(_ids[3 * n], _ids[3 * n + 1], _ids[3 * n + 2])] = n;
            _indexById = map;
        }

        private void CheckIndex(int index)
        {
            if ((uint)index >= (uint)Count)
                throw new ArgumentOutOfRangeException(nameof(index), index, "point index must be in 0.." + (Count - 1));
        }

        /// <summary>Memory a grid of <paramref name="pointCount"/> points needs through the whole pipeline
        /// (ids, positions, SH, features, score, label, id lookup, and the 14-direction lighting cache of the
        /// feature extractor), shown before anything heavy runs.</summary>
        public static long EstimateBytes(long pointCount, int featureCount) =>
            pointCount * (12 + 12 + 108 + 4L * featureCount + 4 + 1 + 32 + 168);
    }
}
