using System;
using System.Collections.Generic;
using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Core.Grid
{
    /// <summary>The coverage rule of Documentation~/grid.md for one box: which lattice points' closed cells
    /// touch it, computed one row (fixed j, k) at a time with the separating-axis theorem.</summary>
    internal sealed class BoxCoverage
    {
        /// <summary>Relative slack (in cells) that makes "exactly touching" robust to rounding.</summary>
        internal const double TouchTolerance = 1e-9;

        private readonly double _cellSize;
        private readonly List<Axis> _axes = new List<Axis>(15);

        public long IMin { get; }
        public long IMax { get; }
        public long JMin { get; }
        public long JMax { get; }
        public long KMin { get; }
        public long KMax { get; }

        /// <summary>Number of (j, k) rows in the box's lattice range (0 when the range is empty).</summary>
        public double RowCount => JMax < JMin || KMax < KMin ? 0 : (double)(JMax - JMin + 1) * (KMax - KMin + 1);

        private struct Axis
        {
            public double X, Y, Z, Reach, CenterProjection;
        }

        public BoxCoverage(GridBox box, double cellSize)
        {
            _cellSize = cellSize;
            double half = cellSize / 2;
            var candidates = new List<Double3> { new Double3(1, 0, 0), new Double3(0, 1, 0), new Double3(0, 0, 1) };
            candidates.Add(Double3.Cross(box.V, box.W));
            candidates.Add(Double3.Cross(box.W, box.U));
            candidates.Add(Double3.Cross(box.U, box.V));
            for (int e = 0; e < 3; e++)
                for (int b = 0; b < 3; b++)
                    candidates.Add(Double3.Cross(candidates[e], box.HalfEdge(b)));
            foreach (var a in candidates)
            {
                if (a.X == 0 && a.Y == 0 && a.Z == 0) continue; // degenerate: parallel edges or a zero half-edge
                _axes.Add(new Axis
                {
                    X = a.X,
                    Y = a.Y,
                    Z = a.Z,
                    Reach = Math.Abs(Double3.Dot(a, box.U)) + Math.Abs(Double3.Dot(a, box.V)) + Math.Abs(Double3.Dot(a, box.W))
                            + half * (Math.Abs(a.X) + Math.Abs(a.Y) + Math.Abs(a.Z)),
                    CenterProjection = a.X * box.Center.X + a.Y * box.Center.Y + a.Z * box.Center.Z,
                });
            }
            IMin = LatticeFloorCeil(box.Center.X - (box.AxisExtent(0) + half), true);
            IMax = LatticeFloorCeil(box.Center.X + (box.AxisExtent(0) + half), false);
            JMin = LatticeFloorCeil(box.Center.Y - (box.AxisExtent(1) + half), true);
            JMax = LatticeFloorCeil(box.Center.Y + (box.AxisExtent(1) + half), false);
            KMin = LatticeFloorCeil(box.Center.Z - (box.AxisExtent(2) + half), true);
            KMax = LatticeFloorCeil(box.Center.Z + (box.AxisExtent(2) + half), false);
        }

        /// <summary>Lattice index bounding a world coordinate: ceil for a lower end, floor for an upper end,
        /// with the touch tolerance. Indices are returned as long; range checks happen in the builder.</summary>
        private long LatticeFloorCeil(double coordinate, bool lower)
        {
            double cells = coordinate / _cellSize;
            double index = lower ? Math.Ceiling(cells - TouchTolerance) : Math.Floor(cells + TouchTolerance);
            if (double.IsNaN(index) || Math.Abs(index) > LatticeId.MaxBuiltCoordinate)
                throw new GridException(
                    "cell size " + InvariantFormat.Number(_cellSize) + " is too small for bounds reaching " +
                    InvariantFormat.Number(coordinate) + ": lattice ids would exceed ±2^23 cells from the origin, where float32 " +
                    "positions can no longer tell neighbouring points apart; use a larger cell size or move the volume closer to the origin");
            return (long)index;
        }

        /// <summary>The covered i range of row (j, k), or false when the row misses the box.</summary>
        public bool TryRow(long j, long k, out long iStart, out long iEnd)
        {
            double y = _cellSize * j, z = _cellSize * k;
            double xLow = double.NegativeInfinity, xHigh = double.PositiveInfinity;
            foreach (var a in _axes)
            {
                double q = a.Y * y + a.Z * z - a.CenterProjection;
                if (a.X == 0)
                {
                    if (Math.Abs(q) > a.Reach + TouchTolerance * _cellSize * (Math.Abs(a.Y) + Math.Abs(a.Z)))
                    {
                        iStart = iEnd = 0;
                        return false;
                    }
                    continue;
                }
                double first = (-a.Reach - q) / a.X, second = (a.Reach - q) / a.X;
                double low = Math.Min(first, second), high = Math.Max(first, second);
                if (low > xLow) xLow = low;
                if (high < xHigh) xHigh = high;
            }
            iStart = Math.Max(IMin, (long)Math.Ceiling(xLow / _cellSize - TouchTolerance));
            iEnd = Math.Min(IMax, (long)Math.Floor(xHigh / _cellSize + TouchTolerance));
            return iStart <= iEnd;
        }
    }
}
