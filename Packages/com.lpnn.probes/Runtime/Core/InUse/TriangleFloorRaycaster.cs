using System;
using System.Numerics;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Core.InUse
{
    /// <summary>The in-use rule's floor rays (Documentation~/in-use.md "Definitions" 1 and 4) against a triangle soup, such as
    /// a navigation mesh's triangulation: rays straight down only (the floor raycaster of InUseMask.Compute never casts
    /// another direction), each triangle found through a grid of buckets over the horizontal plane. A triangle is hit
    /// where the ray passes through it or along its edges (shared edges hit both neighbours, at the same distance);
    /// vertical triangles are never hit (a vertical ray grazes them at most). Normals face either way, as the rule allows.</summary>
    internal sealed class TriangleFloorRaycaster : IRaycaster
    {
        /// <summary>At most this many buckets per triangle (and in all): a soup of a few large triangles stays small.</summary>
        private const int BucketsPerTriangle = 4;
        private const int MaxBuckets = 1 << 22;

        private readonly Double3[] _vertices;
        private readonly int[] _indices;
        private readonly double _minX, _minZ, _maxX, _maxZ, _bucketSize;
        private readonly int _columns, _rows;
        /// <summary>Bucket b holds the triangles _bucketTriangles[_bucketStart[b] .. _bucketStart[b + 1]).</summary>
        private readonly int[] _bucketStart;
        private readonly int[] _bucketTriangles;

        public int TriangleCount => _indices.Length / 3;

        /// <param name="vertices">Positions in metres (finite).</param>
        /// <param name="indices">Three vertex indices per triangle.</param>
        public TriangleFloorRaycaster(Vector3[] vertices, int[] indices)
        {
            if (vertices == null) throw new ArgumentNullException(nameof(vertices));
            if (indices == null) throw new ArgumentNullException(nameof(indices));
            if (indices.Length % 3 != 0)
                throw new ArgumentException("a triangle list needs three indices per triangle; got " + indices.Length, nameof(indices));
            _vertices = new Double3[vertices.Length];
            for (int v = 0; v < vertices.Length; v++)
            {
                _vertices[v] = Double3.FromVector3(vertices[v]);
                if (!_vertices[v].IsFinite)
                    throw new ArgumentException("vertex " + v + " is " + InvariantFormat.Vector(vertices[v]) + ", not finite", nameof(vertices));
            }
            for (int i = 0; i < indices.Length; i++)
                if ((uint)indices[i] >= (uint)vertices.Length)
                    throw new ArgumentException("index " + i + " is " + indices[i] + ", outside the " + vertices.Length + " vertices", nameof(indices));
            _indices = (int[])indices.Clone();

            int triangles = TriangleCount;
            double minX = double.PositiveInfinity, minZ = double.PositiveInfinity, maxX = double.NegativeInfinity, maxZ = double.NegativeInfinity;
            foreach (int index in _indices)
            {
                var v = _vertices[index];
                minX = Math.Min(minX, v.X);
                minZ = Math.Min(minZ, v.Z);
                maxX = Math.Max(maxX, v.X);
                maxZ = Math.Max(maxZ, v.Z);
            }
            if (triangles == 0) minX = minZ = maxX = maxZ = 0;
            _minX = minX;
            _minZ = minZ;
            _maxX = maxX;
            _maxZ = maxZ;
            // About one triangle per bucket over the covered rectangle, never more than BucketsPerTriangle buckets per triangle.
            double width = Math.Max(maxX - minX, 1e-9), depth = Math.Max(maxZ - minZ, 1e-9);
            long budget = Math.Min(MaxBuckets, Math.Max(1L, (long)triangles * BucketsPerTriangle));
            _bucketSize = Math.Max(Math.Sqrt(width * depth / Math.Max(1, triangles)), Math.Sqrt(width * depth / budget));
            _bucketSize = Math.Max(_bucketSize, Math.Max(width, depth) / MaxBuckets);
            _columns = (int)Math.Min(MaxBuckets, Math.Floor(width / _bucketSize) + 1);
            _rows = (int)Math.Min(MaxBuckets / _columns, Math.Floor(depth / _bucketSize) + 1);

            var counts = new int[_columns * _rows + 1];
            ForEachBucket((triangle, bucket) => counts[bucket + 1]++);
            for (int b = 0; b < counts.Length - 1; b++) counts[b + 1] += counts[b];
            _bucketStart = counts;
            _bucketTriangles = new int[counts[counts.Length - 1]];
            var filled = new int[_columns * _rows];
            ForEachBucket((triangle, bucket) => _bucketTriangles[_bucketStart[bucket] + filled[bucket]++] = triangle);
        }

        /// <summary>Casts each ray straight down; an error for any other direction.</summary>
        public void Cast(Vector3[] origins, Vector3[] directions, float maxDistance, RayHit[] results)
        {
            for (int r = 0; r < origins.Length; r++)
            {
                var direction = directions[r];
                if (direction.X != 0 || direction.Z != 0 || !(direction.Y < 0))
                    throw new ArgumentException("ray " + r + " has direction " + InvariantFormat.Vector(direction) + ": the triangle floor " +
                                                "raycaster casts straight down only (0, -1, 0)", nameof(directions));
                results[r] = CastDown(Double3.FromVector3(origins[r]), maxDistance);
            }
        }

        private RayHit CastDown(Double3 origin, double maxDistance)
        {
            var hit = RayHit.Miss;
            if (TriangleCount == 0) return hit;
            if (!(origin.X >= _minX && origin.X <= _maxX && origin.Z >= _minZ && origin.Z <= _maxZ)) return hit;
            // Clamped as the triangles were filed (ForEachBucket): the last row and column also hold what lies beyond them.
            int bucket = Clamp((int)Math.Floor((origin.Z - _minZ) / _bucketSize), _rows) * _columns +
                         Clamp((int)Math.Floor((origin.X - _minX) / _bucketSize), _columns);
            double best = double.PositiveInfinity;
            for (int t = _bucketStart[bucket]; t < _bucketStart[bucket + 1]; t++)
            {
                int triangle = _bucketTriangles[t];
                var a = _vertices[_indices[3 * triangle]];
                var b = _vertices[_indices[3 * triangle + 1]];
                var c = _vertices[_indices[3 * triangle + 2]];
                // Barycentric weights in the horizontal plane: signed areas of the sub-triangles opposite each vertex.
                double wa = Cross2(b, c, origin), wb = Cross2(c, a, origin), wc = Cross2(a, b, origin);
                double area = wa + wb + wc;
                if (area == 0) continue;  // vertical (or degenerate) triangle
                bool inside = area > 0 ? wa >= 0 && wb >= 0 && wc >= 0 : wa <= 0 && wb <= 0 && wc <= 0;
                if (!inside) continue;
                double floorY = (wa * a.Y + wb * b.Y + wc * c.Y) / area;
                double distance = origin.Y - floorY;
                if (distance < 0 || distance > maxDistance || distance >= best) continue;
                best = distance;
                var normal = Double3.Cross(b - a, c - a);
                normal = normal * (1 / normal.Length);
                hit = new RayHit { Distance = (float)distance, Normal = new Vector3((float)normal.X, (float)normal.Y, (float)normal.Z) };
            }
            return hit;
        }

        /// <summary>Twice the signed area of (p, q, r) in the horizontal (x, z) plane.</summary>
        private static double Cross2(Double3 p, Double3 q, Double3 r) => (q.X - p.X) * (r.Z - p.Z) - (q.Z - p.Z) * (r.X - p.X);

        private void ForEachBucket(Action<int, int> visit)
        {
            for (int triangle = 0; triangle < TriangleCount; triangle++)
            {
                double lowX = double.PositiveInfinity, lowZ = double.PositiveInfinity, highX = double.NegativeInfinity, highZ = double.NegativeInfinity;
                for (int corner = 0; corner < 3; corner++)
                {
                    var v = _vertices[_indices[3 * triangle + corner]];
                    lowX = Math.Min(lowX, v.X);
                    lowZ = Math.Min(lowZ, v.Z);
                    highX = Math.Max(highX, v.X);
                    highZ = Math.Max(highZ, v.Z);
                }
                int c0 = Clamp((int)Math.Floor((lowX - _minX) / _bucketSize), _columns), c1 = Clamp((int)Math.Floor((highX - _minX) / _bucketSize), _columns);
                int r0 = Clamp((int)Math.Floor((lowZ - _minZ) / _bucketSize), _rows), r1 = Clamp((int)Math.Floor((highZ - _minZ) / _bucketSize), _rows);
                for (int row = r0; row <= r1; row++)
                for (int column = c0; column <= c1; column++)
                    visit(triangle, row * _columns + column);
            }
        }

        private static int Clamp(int value, int count) => Math.Max(0, Math.Min(count - 1, value));
    }
}
