using System;

namespace Lpnn.Probes.Core.Quality
{
    /// <summary>Finds the tetrahedron containing a point through a uniform bucket grid over the tetrahedra's bounding
    /// boxes: each bucket lists the tetrahedra whose (slightly padded) box overlaps it, so a query tests only the few
    /// tetrahedra near the point instead of scanning them all (the linear scan that cost LumiProbes 76–95 % of its time).
    ///
    /// Among the candidates the point takes the one it is clearly inside (smallest barycentric weight above
    /// <see cref="ClearlyInside"/>: at most one), else — on a face, edge or vertex shared by several, within
    /// <see cref="InsideTolerance"/> — the lowest-index tetrahedron it is inside within that tolerance (Documentation~/quality.md §1
    /// "Ties", as the Python reference's walk): a point on a shared face gets the same interpolated value from either side
    /// but the cell the insertion ranking groups it by must not hang on rounding, and a point a rounding error outside every
    /// tetrahedron still finds the right one.</summary>
    internal sealed class TetrahedronLocator
    {
        /// <summary>A barycentric weight ≥ −this counts as inside (Documentation~/quality.md §1).</summary>
        public const double InsideTolerance = 1e-9;

        /// <summary>Box padding in local units: far more than the inside tolerance can reach, so no candidate is missed.</summary>
        private const double Padding = 1e-7;

        /// <summary>Aim for about this many buckets per tetrahedron (a bucket then holds a handful).</summary>
        private const double BucketsPerTetrahedron = 0.5;

        private readonly TetrahedralMesh _mesh;
        private readonly double _minX, _minY, _minZ, _maxX, _maxY, _maxZ;
        private double _bucket;
        private int _nx, _ny, _nz;
        private readonly int[] _start;
        private readonly int[] _items;

        public TetrahedronLocator(TetrahedralMesh mesh)
        {
            _mesh = mesh;
            int tetCount = mesh.TetrahedronCount;
            var bounds = new double[6 * tetCount];
            _minX = _minY = _minZ = double.PositiveInfinity;
            _maxX = _maxY = _maxZ = double.NegativeInfinity;
            // Comparisons written out, as Math.Min/Max give them for numbers (Mono calls those, once per comparison).
            for (int t = 0; t < tetCount; t++)
            {
                BoundsOf(t, bounds);
                _minX = _minX < bounds[6 * t] ? _minX : bounds[6 * t];
                _minY = _minY < bounds[6 * t + 1] ? _minY : bounds[6 * t + 1];
                _minZ = _minZ < bounds[6 * t + 2] ? _minZ : bounds[6 * t + 2];
                _maxX = _maxX > bounds[6 * t + 3] ? _maxX : bounds[6 * t + 3];
                _maxY = _maxY > bounds[6 * t + 4] ? _maxY : bounds[6 * t + 4];
                _maxZ = _maxZ > bounds[6 * t + 5] ? _maxZ : bounds[6 * t + 5];
            }
            double ex = _maxX - _minX, ey = _maxY - _minY, ez = _maxZ - _minZ;
            // Cubic buckets whose count is about BucketsPerTetrahedron × T (the padded box always has volume > 0).
            _bucket = Math.Pow(ex * ey * ez / Math.Max(1.0, BucketsPerTetrahedron * tetCount), 1.0 / 3.0);
            _nx = Cells(ex);
            _ny = Cells(ey);
            _nz = Cells(ez);
            // Thin or elongated hulls round many axes up; grow the buckets until their count is proportional to T again.
            while ((long)_nx * _ny * _nz > 2L * tetCount + 64)
            {
                _bucket *= 1.25;
                _nx = Cells(ex);
                _ny = Cells(ey);
                _nz = Cells(ez);
            }
            var counts = new int[_nx * _ny * _nz + 1];
            ForEachBucket(bounds, tetCount, counts, null);
            for (int b = 1; b < counts.Length; b++) counts[b] += counts[b - 1];
            _start = (int[])counts.Clone();
            _items = new int[counts[counts.Length - 1]];
            ForEachBucket(bounds, tetCount, counts, _items);
        }

        private int Cells(double extent) => (int)Math.Max(1, Math.Min(1 << 20, Math.Ceiling(extent / _bucket)));

        private void BoundsOf(int t, double[] bounds)
        {
            double[] p = _mesh.Points;
            int o = 6 * t;
            for (int axis = 0; axis < 3; axis++)
            {
                double lo = double.PositiveInfinity, hi = double.NegativeInfinity;
                for (int k = 0; k < 4; k++)
                {
                    double v = p[3 * _mesh.Tetrahedra[4 * t + k] + axis];
                    lo = lo < v ? lo : v;  // Math.Min(lo, v), Math.Max(hi, v) for numbers (the constructor's note)
                    hi = hi > v ? hi : v;
                }
                bounds[o + axis] = lo - Padding;
                bounds[o + 3 + axis] = hi + Padding;
            }
        }

        /// <summary>For every bucket each tetrahedron's box overlaps, tetrahedra in ascending order (so each bucket lists
        /// them ascending): without <paramref name="items"/>, counts it in <paramref name="counts"/>[bucket + 1]; with them,
        /// files the tetrahedron at items[counts[bucket]++]. (Two loops, not a delegate per visit: Mono does not inline it.)</summary>
        private void ForEachBucket(double[] bounds, int tetCount, int[] counts, int[] items)
        {
            for (int t = 0; t < tetCount; t++)
            {
                int x0 = Cell(bounds[6 * t], _minX, _nx), x1 = Cell(bounds[6 * t + 3], _minX, _nx);
                int y0 = Cell(bounds[6 * t + 1], _minY, _ny), y1 = Cell(bounds[6 * t + 4], _minY, _ny);
                int z0 = Cell(bounds[6 * t + 2], _minZ, _nz), z1 = Cell(bounds[6 * t + 5], _minZ, _nz);
                for (int z = z0; z <= z1; z++)
                for (int y = y0; y <= y1; y++)
                for (int x = x0; x <= x1; x++)
                {
                    int bucket = (z * _ny + y) * _nx + x;
                    if (items == null) counts[bucket + 1]++;
                    else items[counts[bucket]++] = t;
                }
            }
        }

        private int Cell(double v, double min, int cells) => Math.Min(cells - 1, Math.Max(0, (int)Math.Floor((v - min) / _bucket)));

        /// <summary>The tetrahedron containing (x, y, z) (local frame) by the class text's rule, and its barycentric weights
        /// clamped to ≥ 0 and renormalised; false when the point is outside every tetrahedron.</summary>
        public bool TryLocate(double x, double y, double z, double[] weights, out int tetrahedron)
        {
            tetrahedron = -1;
            if (x < _minX || x > _maxX || y < _minY || y > _maxY || z < _minZ || z > _maxZ) return false;
            int bucket = (Cell(z, _minZ, _nz) * _ny + Cell(y, _minY, _ny)) * _nx + Cell(x, _minX, _nx);
            int lowest = -1;
            double c0 = 0, c1 = 0, c2 = 0, c3 = 0;
            // The bucket lists its tetrahedra in ascending order, so the first one within the tolerance is the lowest.
            for (int i = _start[bucket]; i < _start[bucket + 1]; i++)
            {
                int t = _items[i];
                Barycentric(t, x, y, z, out double l0, out double l1, out double l2, out double l3);
                double l01 = l0 < l1 ? l0 : l1, l23 = l2 < l3 ? l2 : l3;  // Smallest, inline: the hottest loop
                double smallest = l01 < l23 ? l01 : l23;
                if (smallest > ClearlyInside)
                {
                    // The only tetrahedron the point is clearly inside (ClearlyInside), so the one of largest smallest
                    // weight: found without testing the rest.
                    tetrahedron = t;
                    Normalised(l0, l1, l2, l3, weights);
                    return true;
                }
                if (lowest < 0 && smallest >= -InsideTolerance)
                {
                    lowest = t;
                    c0 = l0; c1 = l1; c2 = l2; c3 = l3;
                }
            }
            if (lowest < 0) return false;  // outside every tetrahedron by more than the tolerance
            tetrahedron = lowest;  // on a shared boundary: the tie rule
            Normalised(c0, c1, c2, c3, weights);
            return true;
        }

        /// <summary>A point whose smallest barycentric weight in a tetrahedron is above this lies in no other tetrahedron
        /// (they do not overlap, and rounding stays far below it): <see cref="TryLocate"/> finds it there. At or below it
        /// (and ≥ −<see cref="InsideTolerance"/>) the point is on the tetrahedron's boundary, where the tie rule decides.</summary>
        public const double ClearlyInside = InsideTolerance;

        /// <summary>The weights of (x, y, z) in tetrahedron <paramref name="t"/>, as <see cref="TryLocate"/> gives them (the
        /// same numbers), when the point is clearly inside it (<see cref="ClearlyInside"/>): then TryLocate would find it
        /// there. False for a point on or near its boundary (a face, edge or vertex it may share with another tetrahedron,
        /// where TryLocate takes the lowest-index one): locate that one. For an insertion round's point whose tetrahedron
        /// survived the insertion (<see cref="InsertionRounds"/>).</summary>
        public bool TryWeightsIn(int t, double x, double y, double z, double[] weights)
        {
            Barycentric(t, x, y, z, out double b0, out double b1, out double b2, out double b3);
            if (!(Smallest(b0, b1, b2, b3) > ClearlyInside)) return false;
            Normalised(b0, b1, b2, b3, weights);
            return true;
        }

        /// <summary>Math.Min(Math.Min(a, b), Math.Min(c, d)) for numbers, written out (the constructor's note).</summary>
        private static double Smallest(double a, double b, double c, double d)
        {
            double ab = a < b ? a : b, cd = c < d ? c : d;
            return ab < cd ? ab : cd;
        }

        /// <summary>Clamped to ≥ 0 and renormalised.</summary>
        private static void Normalised(double b0, double b1, double b2, double b3, double[] weights)
        {
            // Math.Max(0, b) as Mono gives it (b when equal: −0 stays −0), written out (the constructor's note).
            b0 = 0.0 > b0 ? 0.0 : b0;
            b1 = 0.0 > b1 ? 0.0 : b1;
            b2 = 0.0 > b2 ? 0.0 : b2;
            b3 = 0.0 > b3 ? 0.0 : b3;
            // The largest weight is ≥ 1/4 − 4e-9 before clamping, so the sum is never 0.
            double sum = b0 + b1 + b2 + b3;
            weights[0] = b0 / sum;
            weights[1] = b1 / sum;
            weights[2] = b2 / sum;
            weights[3] = b3 / sum;
        }

        private void Barycentric(int t, double x, double y, double z, out double l0, out double l1, out double l2, out double l3)
        {
            double[] p = _mesh.Points, m = _mesh.Inverse;
            int v0 = _mesh.Tetrahedra[4 * t], o = 9 * t;
            double qx = x - p[3 * v0], qy = y - p[3 * v0 + 1], qz = z - p[3 * v0 + 2];
            l1 = m[o] * qx + m[o + 1] * qy + m[o + 2] * qz;
            l2 = m[o + 3] * qx + m[o + 4] * qy + m[o + 5] * qz;
            l3 = m[o + 6] * qx + m[o + 7] * qy + m[o + 8] * qz;
            l0 = 1.0 - (l1 + l2 + l3);
        }
    }
}
