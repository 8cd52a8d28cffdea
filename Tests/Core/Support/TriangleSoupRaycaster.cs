using System;
using System.IO;
using System.Numerics;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Core.Tests.Support
{
    /// <summary>First-hit rays against a triangle soup through a bounding-volume hierarchy, in double precision: the stand-in
    /// for Unity's physics (and for the Embree raycaster `lpnn place` casts through, lpnn/scenes/raycast.py) when the C#
    /// core's leak-aware Apply runs on a real level's geometry outside Unity (the Apply benchmark,
    /// Tools~/experiments/SelectionBench/ApplyBench.cs). Both facings are hit, as Unity's hitBackfaces and Embree; a ray
    /// through a triangle's edge or vertex hits it (edges inclusive), so a ray through the shared edge of two triangles of
    /// a wall cannot slip between them. Parallel rays in a triangle's plane never hit it. Test and bench code, not Runtime:
    /// Unity casts through its own physics. Each ray may end at its own distance (<see cref="IPerRayDistanceRaycaster"/>, as
    /// Unity's RaycastCommand and Embree's per-ray tfar). <see cref="RaysCast"/> counts the rays, for the benchmark.</summary>
    public sealed class TriangleSoupRaycaster : IPerRayDistanceRaycaster
    {
        /// <summary>Triangles per leaf at most: below this a leaf's triangles are tested one by one.</summary>
        private const int LeafSize = 4;

        // Per triangle, in the hierarchy's leaf order, its vertices in floats relative to the centre (as Embree gets them), and
        // the unit normal a hit reports.
        private readonly float[] _v0, _v1, _v2;
        private readonly Vector3[] _normal;
        // Per node: its box (6 doubles: min xyz, max xyz), and either its first child (the second is the next node after the
        // first's subtree: _second) or, for a leaf, its triangles [_first, _first + _count).
        private readonly double[] _box;
        private readonly int[] _first, _count, _second;
        private int _nodes;
        private double[] _keys;  // the build's sort keys, by position in its order

        public int TriangleCount { get; }

        /// <summary>The centre of the vertices' bounding box: vertices and ray origins are taken relative to it and rounded to
        /// float, as lpnn/scenes/raycast.py hands them to Embree, so the rays a lattice casts exactly along or through a wall's
        /// edge decide as they do in `lpnn place`.</summary>
        private readonly Double3 _centre;

        /// <summary>Rays cast so far (every ray of every <see cref="Cast"/> call).</summary>
        public long RaysCast { get; private set; }

        /// <param name="vertices">Positions in metres (finite).</param>
        /// <param name="indices">Three vertex indices per triangle.</param>
        public TriangleSoupRaycaster(Double3[] vertices, int[] indices)
        {
            if (vertices == null) throw new ArgumentNullException(nameof(vertices));
            if (indices == null) throw new ArgumentNullException(nameof(indices));
            if (indices.Length % 3 != 0)
                throw new ArgumentException("a triangle list needs three indices per triangle; got " + indices.Length, nameof(indices));
            for (int v = 0; v < vertices.Length; v++)
                if (!vertices[v].IsFinite) throw new ArgumentException("vertex " + v + " is not finite", nameof(vertices));
            foreach (int index in indices)
                if ((uint)index >= (uint)vertices.Length)
                    throw new ArgumentException("index " + index + " is outside the " + vertices.Length + " vertices", nameof(indices));
            int triangles = indices.Length / 3;
            TriangleCount = triangles;
            if (vertices.Length > 0)
            {
                double loX = double.PositiveInfinity, loY = double.PositiveInfinity, loZ = double.PositiveInfinity;
                double hiX = double.NegativeInfinity, hiY = double.NegativeInfinity, hiZ = double.NegativeInfinity;
                foreach (var v in vertices)
                {
                    loX = Math.Min(loX, v.X); loY = Math.Min(loY, v.Y); loZ = Math.Min(loZ, v.Z);
                    hiX = Math.Max(hiX, v.X); hiY = Math.Max(hiY, v.Y); hiZ = Math.Max(hiZ, v.Z);
                }
                _centre = new Double3((loX + hiX) / 2, (loY + hiY) / 2, (loZ + hiZ) / 2);
            }
            vertices = Array.ConvertAll(vertices, v => Rounded(v - _centre));
            var order = new int[triangles];
            var centroid = new Double3[triangles];
            for (int t = 0; t < triangles; t++)
            {
                order[t] = t;
                centroid[t] = (vertices[indices[3 * t]] + vertices[indices[3 * t + 1]] + vertices[indices[3 * t + 2]]) * (1.0 / 3.0);
            }
            int maxNodes = Math.Max(1, 2 * triangles);
            _box = new double[6 * maxNodes];
            _first = new int[maxNodes];
            _count = new int[maxNodes];
            _second = new int[maxNodes];
            _keys = new double[triangles];
            if (triangles > 0) Build(vertices, indices, order, centroid, 0, triangles);
            _keys = null;
            _v0 = new float[3 * triangles];
            _v1 = new float[3 * triangles];
            _v2 = new float[3 * triangles];
            _normal = new Vector3[triangles];
            for (int k = 0; k < triangles; k++)
            {
                int t = order[k];
                Double3 a = vertices[indices[3 * t]], b = vertices[indices[3 * t + 1]], c = vertices[indices[3 * t + 2]];
                Set(_v0, k, a);
                Set(_v1, k, b);
                Set(_v2, k, c);
                var n = Double3.Cross(b - a, c - a);
                double length = n.Length;
                _normal[k] = length > 0 ? new Vector3((float)(n.X / length), (float)(n.Y / length), (float)(n.Z / length)) : Vector3.Zero;
            }
        }

        /// <summary>Reads the triangles Tools~/experiments/SelectionBench/write_capture_triangles.py writes (little-endian int32 V,
        /// int32 T, V x 3 float64 vertices, T x 3 int32 indices).</summary>
        public static TriangleSoupRaycaster Read(string path)
        {
            using (var reader = new BinaryReader(File.OpenRead(path)))
            {
                int vertexCount = reader.ReadInt32(), triangleCount = reader.ReadInt32();
                if (vertexCount < 0 || triangleCount < 0) throw new InvalidDataException(path + ": negative counts");
                var vertices = new Double3[vertexCount];
                for (int v = 0; v < vertexCount; v++) vertices[v] = new Double3(reader.ReadDouble(), reader.ReadDouble(), reader.ReadDouble());
                var indices = new int[3 * triangleCount];
                for (int i = 0; i < indices.Length; i++) indices[i] = reader.ReadInt32();
                if (reader.BaseStream.Position != reader.BaseStream.Length) throw new InvalidDataException(path + ": bytes after the triangles");
                return new TriangleSoupRaycaster(vertices, indices);
            }
        }

        private static Double3 Rounded(Double3 v) => new Double3((float)v.X, (float)v.Y, (float)v.Z);

        private static void Set(float[] array, int k, Double3 value)
        {
            array[3 * k] = (float)value.X;
            array[3 * k + 1] = (float)value.Y;
            array[3 * k + 2] = (float)value.Z;
        }

        // Float arithmetic as Embree's kernels do it on this machine (AVX2/AVX-512: fused multiply-adds in dot and cross):
        // each result rounded to float once. A product of two floats is exact in double, so rounding it (plus a float) to
        // float is the fused operation's single rounding, but for the rare double rounding of the sum.
        private static float Mul(float a, float b) => (float)((double)a * b);
        private static float Sub(float a, float b) => (float)((double)a - b);
        private static float Madd(float a, float b, float c) => (float)((double)a * b + c);
        private static float Msub(float a, float b, float c) => (float)((double)a * b - c);
        /// <summary>Embree's dot(a, b) = madd(a.x, b.x, madd(a.y, b.y, a.z * b.z)).</summary>
        private static float Dot(float ax, float ay, float az, float bx, float by, float bz) => Madd(ax, bx, Madd(ay, by, Mul(az, bz)));

        /// <summary>The node of order[start, stop): a leaf of at most <see cref="LeafSize"/> triangles, else split at the median
        /// centroid along the widest axis of the centroids (its triangles reordered in place). Returns the node's index.</summary>
        private int Build(Double3[] vertices, int[] indices, int[] order, Double3[] centroid, int start, int stop)
        {
            int node = _nodes++;
            double minX = double.PositiveInfinity, minY = double.PositiveInfinity, minZ = double.PositiveInfinity;
            double maxX = double.NegativeInfinity, maxY = double.NegativeInfinity, maxZ = double.NegativeInfinity;
            double cMinX = double.PositiveInfinity, cMinY = double.PositiveInfinity, cMinZ = double.PositiveInfinity;
            double cMaxX = double.NegativeInfinity, cMaxY = double.NegativeInfinity, cMaxZ = double.NegativeInfinity;
            for (int k = start; k < stop; k++)
            {
                int t = order[k];
                for (int corner = 0; corner < 3; corner++)
                {
                    var v = vertices[indices[3 * t + corner]];
                    minX = Math.Min(minX, v.X); minY = Math.Min(minY, v.Y); minZ = Math.Min(minZ, v.Z);
                    maxX = Math.Max(maxX, v.X); maxY = Math.Max(maxY, v.Y); maxZ = Math.Max(maxZ, v.Z);
                }
                var c = centroid[t];
                cMinX = Math.Min(cMinX, c.X); cMinY = Math.Min(cMinY, c.Y); cMinZ = Math.Min(cMinZ, c.Z);
                cMaxX = Math.Max(cMaxX, c.X); cMaxY = Math.Max(cMaxY, c.Y); cMaxZ = Math.Max(cMaxZ, c.Z);
            }
            _box[6 * node] = minX; _box[6 * node + 1] = minY; _box[6 * node + 2] = minZ;
            _box[6 * node + 3] = maxX; _box[6 * node + 4] = maxY; _box[6 * node + 5] = maxZ;
            int count = stop - start;
            double spanX = cMaxX - cMinX, spanY = cMaxY - cMinY, spanZ = cMaxZ - cMinZ;
            if (count <= LeafSize || Math.Max(spanX, Math.Max(spanY, spanZ)) <= 0)
            {
                _first[node] = start;
                _count[node] = count;
                return node;
            }
            int axis = spanX >= spanY && spanX >= spanZ ? 0 : spanY >= spanZ ? 1 : 2;
            for (int k = start; k < stop; k++) _keys[k] = centroid[order[k]][axis];
            Array.Sort(_keys, order, start, count);
            int middle = start + count / 2;
            _count[node] = 0;
            _first[node] = Build(vertices, indices, order, centroid, start, middle);
            _second[node] = Build(vertices, indices, order, centroid, middle, stop);
            return node;
        }

        public void Cast(Vector3[] origins, Vector3[] directions, float maxDistance, RayHit[] results) =>
            CastEach(origins, directions, maxDistance, null, results);

        /// <summary>Ray n up to maxDistances[n]: its own tfar, as Embree's (the hit test and the boxes' culling both stop there).</summary>
        public void Cast(Vector3[] origins, Vector3[] directions, float[] maxDistances, RayHit[] results)
        {
            if (maxDistances == null) throw new ArgumentNullException(nameof(maxDistances));
            CastEach(origins, directions, 0, maxDistances, results);
        }

        /// <summary>Ray n up to maxDistances[n], or up to <paramref name="maxDistance"/> when maxDistances is null.</summary>
        private void CastEach(Vector3[] origins, Vector3[] directions, float maxDistance, float[] maxDistances, RayHit[] results)
        {
            if (origins == null) throw new ArgumentNullException(nameof(origins));
            if (directions == null) throw new ArgumentNullException(nameof(directions));
            if (results == null) throw new ArgumentNullException(nameof(results));
            if (directions.Length < origins.Length || results.Length < origins.Length || (maxDistances != null && maxDistances.Length < origins.Length))
                throw new ArgumentException("fewer directions, maximum distances or results than origins");
            var stack = new int[64];
            for (int r = 0; r < origins.Length; r++)
                results[r] = CastOne(origins[r], directions[r], maxDistances == null ? maxDistance : maxDistances[r], stack);
            RaysCast += origins.Length;
        }

        private RayHit CastOne(Vector3 origin, Vector3 direction, double maxDistance, int[] stack)
        {
            var local = Rounded(Double3.FromVector3(origin) - _centre);
            float ox = (float)local.X, oy = (float)local.Y, oz = (float)local.Z, dx = direction.X, dy = direction.Y, dz = direction.Z;
            double ix = 1.0 / dx, iy = 1.0 / dy, iz = 1.0 / dz;
            float best = (float)maxDistance;
            int hit = -1;
            if (_nodes == 0) return RayHit.Miss;
            int top = 0;
            stack[top++] = 0;
            while (top > 0)
            {
                int node = stack[--top];
                if (!Enters(node, ox, oy, oz, dx, dy, dz, ix, iy, iz, best)) continue;
                int count = _count[node];
                if (count == 0)
                {
                    stack[top++] = _second[node];
                    stack[top++] = _first[node];
                    continue;
                }
                for (int k = _first[node], end = _first[node] + count; k < end; k++)
                {
                    // The nearest hit within the maximum distance, as Embree shortens the ray at each hit: a later triangle
                    // must be hit no farther (equal distances keep the first found; either normal is allowed).
                    float t = Intersect(k, ox, oy, oz, dx, dy, dz, best);
                    if (t >= 0 && (hit < 0 || t < best))
                    {
                        best = t;
                        hit = k;
                    }
                }
            }
            return hit < 0 ? RayHit.Miss : new RayHit { Distance = (float)best, Normal = _normal[hit] };
        }

        /// <summary>Whether the ray may meet the node's box at a distance in [0, <paramref name="limit"/>] (slab test, with
        /// slack; an axis the ray runs parallel to is met only from inside its slab, widened alike).</summary>
        private bool Enters(int node, double ox, double oy, double oz, double dx, double dy, double dz, double ix, double iy, double iz, double limit)
        {
            int b = 6 * node;
            double near = 0, far = limit;
            if (!Slab(_box[b], _box[b + 3], ox, dx, ix, ref near, ref far)) return false;
            if (!Slab(_box[b + 1], _box[b + 4], oy, dy, iy, ref near, ref far)) return false;
            return Slab(_box[b + 2], _box[b + 5], oz, dz, iz, ref near, ref far);
        }

        private static bool Slab(double low, double high, double origin, double direction, double inverse, ref double near, ref double far)
        {
            if (direction == 0)
            {
                double margin = 1e-5 * Math.Max(1, Math.Max(Math.Abs(low), Math.Abs(high)));
                return origin >= low - margin && origin <= high + margin;
            }
            double t0 = (low - origin) * inverse, t1 = (high - origin) * inverse;
            if (t0 > t1) { double swap = t0; t0 = t1; t1 = swap; }
            // Widened by float-sized slack: the triangle test's epsilon lets a ray that passes a wall's edge within a few float
            // ulps hit it, so the boxes (flat for a wall) must not reject such a ray first. Any box may be too large; the
            // triangle test decides.
            double slack = 1e-5 * Math.Max(1, Math.Max(Math.Abs(t0), Math.Abs(t1)));
            near = Math.Max(near, t0 - slack);
            far = Math.Min(far, t1 + slack);
            return near <= far;
        }

        /// <summary>Embree 4's Plücker test (kernels/geometry/triangle_intersector_pluecker.h, without backface culling), in its
        /// float arithmetic: the ray's distance to triangle k when it hits it in [0, <paramref name="far"/>], else -1. Its edge
        /// tests allow a relative float epsilon, so a ray through an edge or vertex hits; a ray in the triangle's plane
        /// (den = 0) misses it. The distance is T / den correctly rounded where Embree multiplies by an approximate
        /// reciprocal (a last-bit difference, which only a probe on a surface could notice).</summary>
        private float Intersect(int k, float ox, float oy, float oz, float dx, float dy, float dz, float far)
        {
            int i = 3 * k;
            float ax = Sub(_v0[i], ox), ay = Sub(_v0[i + 1], oy), az = Sub(_v0[i + 2], oz);  // v0 - O
            float bx = Sub(_v1[i], ox), by = Sub(_v1[i + 1], oy), bz = Sub(_v1[i + 2], oz);  // v1 - O
            float cx = Sub(_v2[i], ox), cy = Sub(_v2[i + 1], oy), cz = Sub(_v2[i + 2], oz);  // v2 - O
            float e0x = Sub(cx, ax), e0y = Sub(cy, ay), e0z = Sub(cz, az);  // e0 = v2 - v0
            float e1x = Sub(ax, bx), e1y = Sub(ay, by), e1z = Sub(az, bz);  // e1 = v0 - v1
            float e2x = Sub(bx, cx), e2y = Sub(by, cy), e2z = Sub(bz, cz);  // e2 = v1 - v2
            float u = CrossDot(e0x, e0y, e0z, Add(cx, ax), Add(cy, ay), Add(cz, az), dx, dy, dz);
            float v = CrossDot(e1x, e1y, e1z, Add(ax, bx), Add(ay, by), Add(az, bz), dx, dy, dz);
            float w = CrossDot(e2x, e2y, e2z, Add(bx, cx), Add(by, cy), Add(bz, cz), dx, dy, dz);
            float epsilon = Mul(FloatEpsilon, Math.Abs(Add(Add(u, v), w)));
            if (!(Math.Min(u, Math.Min(v, w)) >= -epsilon || Math.Max(u, Math.Max(v, w)) <= epsilon)) return -1;
            // Embree's stable_triangle_normal(e0, e1, e2): per component, the cross product of the pair with the smaller term.
            float abX = Mul(e0z, e1y), abY = Mul(e0x, e1z), abZ = Mul(e0y, e1x);
            float bcX = Mul(e1z, e2y), bcY = Mul(e1x, e2z), bcZ = Mul(e1y, e2x);
            float nx = Math.Abs(abX) < Math.Abs(bcX) ? Msub(e0y, e1z, abX) : Msub(e1y, e2z, bcX);
            float ny = Math.Abs(abY) < Math.Abs(bcY) ? Msub(e0z, e1x, abY) : Msub(e1z, e2x, bcY);
            float nz = Math.Abs(abZ) < Math.Abs(bcZ) ? Msub(e0x, e1y, abZ) : Msub(e1x, e2y, bcZ);
            float den = 2 * Dot(nx, ny, nz, dx, dy, dz);
            if (den == 0) return -1;
            float t = (float)(2.0 * Dot(ax, ay, az, nx, ny, nz) / den);
            return t >= 0 && t <= far ? t : -1;
        }

        /// <summary>FLT_EPSILON, Embree's ulp.</summary>
        private const float FloatEpsilon = 1.1920929e-7f;

        private static float Add(float a, float b) => (float)((double)a + b);

        /// <summary>Embree's dot(cross(a, b), d).</summary>
        private static float CrossDot(float ax, float ay, float az, float bx, float by, float bz, float dx, float dy, float dz) =>
            Dot(Msub(ay, bz, Mul(az, by)), Msub(az, bx, Mul(ax, bz)), Msub(ax, by, Mul(ay, bx)), dx, dy, dz);
    }
}
