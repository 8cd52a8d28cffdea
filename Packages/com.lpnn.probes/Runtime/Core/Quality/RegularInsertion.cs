using System;
using System.Collections.Generic;

namespace Lpnn.Probes.Core.Quality
{
    /// <summary>A tie-broken Delaunay tetrahedralisation grown by inserting points (Bowyer–Watson on the lifted points,
    /// Documentation~/quality.md §5.1 step 6): each point is lifted to |x|² + h, h its tie height (<see cref="TieBreak"/>),
    /// and its cavity — the tetrahedra whose lifted hyperplane it lies below, and the hull faces it lies beyond (or, in a
    /// hull face's plane, inside that face's power circle) — is re-triangulated from it. The lifted points are in general
    /// position, so the result is the unique regular triangulation of the points: the tetrahedraliser's set of tetrahedra
    /// when it breaks ties as Python's Qhull does, whatever the insertion order. The hull is closed by a vertex at
    /// infinity (one "infinite" tetrahedron per hull face), so points outside the hull grow it.
    ///
    /// Every sign it decides is computed in double with a bound on its rounding (relative to the determinant's
    /// permanent); within the bound it is computed exactly (<see cref="ExactPredicates"/>), so the answer is the regular
    /// triangulation of the given doubles, and only truly coplanar points (a lattice's axis-aligned planes, where every
    /// product of the expansion is 0) or a true lifted tie count as such. The insertion fails (<see cref="TryInsert"/>
    /// returns false, <see cref="Failure"/> says why) on a true lifted tie, a new tetrahedron that is not positively
    /// oriented, or a vertex the cavity would swallow; building the structure fails when the starting tetrahedra are not
    /// a closed convex tetrahedralisation of every vertex (a crack left by a dropped flat tetrahedron, quality.md §1). The
    /// caller then tetrahedralises instead. A point walks to its cavity from the last tetrahedron made (plain double; a
    /// scan of every tetrahedron where the walk stops beside it).</summary>
    internal sealed class RegularInsertion
    {
        private const int Infinite = -1;
        /// <summary>A determinant within this × its permanent of 0 is computed exactly (the double evaluation's rounding is
        /// below ~1e-15 of the permanent; the rest is margin).</summary>
        internal const double UndecidedFraction = 1e-12;
        /// <summary>Vertex indices must fit 21 bits for the face keys.</summary>
        private const int MaxVertices = 1 << 21;

        private readonly double[] _local;   // x, y, z per global point
        private readonly double[] _height;  // tie height per global point
        private int[] _global;              // per vertex: its global point index
        private int _vertexCount;
        private int[] _v = new int[0];      // 4 vertices per tetrahedron (Infinite in slot 3 for a hull face's)
        private int[] _n = new int[0];      // 4 neighbours per tetrahedron, across the face opposite each slot
        private bool[] _alive = new bool[0];
        private int _count;
        private readonly Stack<int> _free = new Stack<int>();
        private int _last;                  // a live tetrahedron to start the next walk from
        private readonly double[] _matrix = new double[16];  // the lifted determinants' rows, reused

        private RegularInsertion(double[] local, double[] height)
        {
            _local = local;
            _height = height;
        }

        /// <summary>The structure of a tetrahedralisation, or null when it is not a closed convex one (class text).</summary>
        /// <param name="local">x, y, z per global point (the reference's local frame).</param>
        /// <param name="height">Tie height per global point, local units squared.</param>
        /// <param name="vertices">The global points of the tetrahedralisation's vertices, in vertex order.</param>
        /// <param name="tetrahedra">4 vertex indices per tetrahedron, any orientation.</param>
        /// <param name="failure">Why it is null (null when it is not).</param>
        public static RegularInsertion Of(double[] local, double[] height, int[] vertices, int[] tetrahedra, out string failure)
        {
            failure = "too many vertices, or no tetrahedra";
            if (vertices.Length >= MaxVertices || tetrahedra.Length == 0 || tetrahedra.Length % 4 != 0) return null;
            var mesh = new RegularInsertion(local, height);
            mesh._global = new int[Math.Max(16, vertices.Length)];
            Array.Copy(vertices, mesh._global, vertices.Length);
            mesh._vertexCount = vertices.Length;
            bool assembled = mesh.Assemble(tetrahedra);
            failure = mesh.Failure;
            return assembled ? mesh : null;
        }

        public int VertexCount => _vertexCount;

        /// <summary>Why the last insertion or the assembly failed (null: it did not), for tests and benches.</summary>
        public string Failure { get; private set; }

        private bool Fail(string reason)
        {
            Failure = reason;
            return false;
        }

        /// <summary>Appends the point as the next vertex and re-triangulates its cavity; false when there is a true tie or
        /// the result would not be a tetrahedralisation with it as a vertex (the structure is then unusable).</summary>
        public bool TryInsert(int point)
        {
            if (_vertexCount + 1 >= MaxVertices) return Fail("too many vertices");
            if (_vertexCount == _global.Length) Array.Resize(ref _global, 2 * _global.Length);
            int p = _vertexCount++;
            _global[p] = point;
            int start = Locate(p);
            // The walk decides in plain double: where it stopped beside the point (within rounding of a face) and not in
            // conflict, any tetrahedron the exact test puts in conflict starts the cavity (it is connected).
            if (start < 0 || Conflict(start, p) != 1) start = AnyInConflict(p);
            if (start < 0) return Fail("no tetrahedron in conflict with the point");
            var cavity = new List<int> { start };
            var inCavity = new HashSet<int> { start };
            var boundary = new List<long>();  // cavity tetrahedron * 4 + slot of a face with an outside tetrahedron across
            for (int k = 0; k < cavity.Count; k++)
            {
                int t = cavity[k];
                for (int j = 0; j < 4; j++)
                {
                    int u = _n[4 * t + j];
                    if (inCavity.Contains(u)) continue;
                    int conflict = Conflict(u, p);
                    if (conflict == 0) return Fail("a true tie (lifted points on one hyperplane)");
                    if (conflict > 0)
                    {
                        inCavity.Add(u);
                        cavity.Add(u);
                    }
                }
            }
            foreach (int t in cavity)
                for (int j = 0; j < 4; j++)
                    if (!inCavity.Contains(_n[4 * t + j])) boundary.Add(4L * t + j);
            var made = new int[boundary.Count];
            var open = new Dictionary<long, long>();  // a new face through p (by its edge) -> new tetrahedron * 4 + slot
            for (int b = 0; b < boundary.Count; b++)
            {
                int t = (int)(boundary[b] >> 2), j = (int)(boundary[b] & 3);
                int fresh = Allocate();
                for (int s = 0; s < 4; s++) _v[4 * fresh + s] = _v[4 * t + s];
                _v[4 * fresh + j] = p;
                if (_v[4 * fresh + 3] != Infinite && !PositivelyOriented(fresh)) return Fail("a new tetrahedron flat or negative (the cavity not star-shaped)");
                int outside = _n[4 * t + j];
                _n[4 * fresh + j] = outside;
                int back = SlotOf(outside, t);
                if (back < 0) return Fail("no way back from outside the cavity");
                _n[4 * outside + back] = fresh;
                made[b] = fresh;
                for (int s = 0; s < 4; s++)
                {
                    if (s == j) continue;
                    long key = EdgeKey(_v, fresh, j, s);
                    if (open.TryGetValue(key, out long other))
                    {
                        int ot = (int)(other >> 2), os = (int)(other & 3);
                        _n[4 * fresh + s] = ot;
                        _n[4 * ot + os] = fresh;
                        open.Remove(key);
                    }
                    else open[key] = 4L * fresh + s;
                }
            }
            if (open.Count != 0) return Fail("a new face unpaired");
            // Every vertex of the cavity must stay one (a regular triangulation may otherwise hide it).
            var kept = new HashSet<int>();
            foreach (int fresh in made)
                for (int s = 0; s < 4; s++) kept.Add(_v[4 * fresh + s]);
            foreach (int t in cavity)
            {
                for (int s = 0; s < 4; s++)
                    if (!kept.Contains(_v[4 * t + s])) return Fail("a vertex would vanish");
                _alive[t] = false;
                _free.Push(t);
            }
            _last = made[0];
            return true;
        }

        /// <summary>The finite tetrahedra, 4 vertex indices each.</summary>
        public int[] Tetrahedra()
        {
            var result = new List<int>(4 * _count);
            for (int t = 0; t < _count; t++)
            {
                if (!_alive[t] || _v[4 * t + 3] == Infinite) continue;
                for (int s = 0; s < 4; s++) result.Add(_v[4 * t + s]);
            }
            return result.ToArray();
        }

        /// <summary>Neighbours across shared faces, and one infinite tetrahedron per hull face with its neighbours across
        /// hull edges; false for anything but a closed, convex, connected tetrahedralisation of every vertex.</summary>
        private bool Assemble(int[] tetrahedra)
        {
            int finite = tetrahedra.Length / 4;
            var used = new bool[_vertexCount];
            var faces = new Dictionary<long, long>(2 * finite);
            for (int k = 0; k < finite; k++)
            {
                int t = Allocate();
                for (int s = 0; s < 4; s++)
                {
                    int vertex = tetrahedra[4 * k + s];
                    if (vertex < 0 || vertex >= _vertexCount) return Fail("a corner out of range");
                    _v[4 * t + s] = vertex;
                    used[vertex] = true;
                }
                int orientation = OrientSign(_v[4 * t], _v[4 * t + 1], _v[4 * t + 2], _v[4 * t + 3]);
                if (orientation == 0) return Fail("a flat tetrahedron");
                if (orientation < 0)
                {
                    int swap = _v[4 * t + 2];
                    _v[4 * t + 2] = _v[4 * t + 3];
                    _v[4 * t + 3] = swap;
                }
                for (int s = 0; s < 4; s++)
                {
                    long key = FaceKey(_v, t, s);
                    if (faces.TryGetValue(key, out long other))
                    {
                        if (other < 0) return Fail("a face of three tetrahedra");  // a third tetrahedron on one face
                        int ot = (int)(other >> 2), os = (int)(other & 3);
                        _n[4 * t + s] = ot;
                        _n[4 * ot + os] = t;
                        faces[key] = -1;
                    }
                    else
                    {
                        faces[key] = 4L * t + s;
                        _n[4 * t + s] = -1;
                    }
                }
            }
            foreach (bool u in used)
                if (!u) return Fail("a vertex in no tetrahedron");
            // Hull faces: an infinite tetrahedron each, its finite face ordered so that the inside is on its negative side.
            var edges = new Dictionary<long, long>();
            int hullFaces = 0;
            for (int t = 0; t < finite; t++)
                for (int s = 0; s < 4; s++)
                {
                    if (_n[4 * t + s] >= 0) continue;
                    OutwardFace(t, s, out int a, out int b, out int c);
                    int h = Allocate();
                    hullFaces++;
                    _v[4 * h] = a;
                    _v[4 * h + 1] = b;
                    _v[4 * h + 2] = c;
                    _v[4 * h + 3] = Infinite;
                    _n[4 * h + 3] = t;
                    _n[4 * t + s] = h;
                    for (int e = 0; e < 3; e++)
                    {
                        long key = EdgeKey(_v, h, 3, e);
                        if (edges.TryGetValue(key, out long other))
                        {
                            if (other < 0) return Fail("a hull edge of three hull faces");
                            int ot = (int)(other >> 2), os = (int)(other & 3);
                            _n[4 * h + e] = ot;
                            _n[4 * ot + os] = h;
                            edges[key] = -1;
                        }
                        else edges[key] = 4L * h + e;
                    }
                }
            foreach (var pair in edges)
                if (pair.Value >= 0) return Fail("a hull edge of one hull face");  // a hull edge of one hull face
            // Convex: across every hull edge the other face's far corner is not beyond this face's plane; connected: one
            // surface (a crack inside would be a second one).
            var seen = new HashSet<int>();
            var queue = new Queue<int>();
            int first = -1;
            for (int t = 0; t < _count && first < 0; t++)
                if (_v[4 * t + 3] == Infinite) first = t;
            queue.Enqueue(first);
            seen.Add(first);
            while (queue.Count > 0)
            {
                int h = queue.Dequeue();
                for (int e = 0; e < 3; e++)
                {
                    int other = _n[4 * h + e];
                    int far = _v[4 * other + SlotOf(other, h)];
                    if (far == Infinite) return Fail("a hull edge of one hull face");
                    if (OrientSign(_v[4 * h], _v[4 * h + 1], _v[4 * h + 2], far) > 0) return Fail("the hull not convex");
                    if (seen.Add(other)) queue.Enqueue(other);
                }
            }
            if (seen.Count != hullFaces) return Fail("the hull in pieces (a crack inside)");
            _last = 0;
            return true;
        }

        /// <summary>The face of finite tetrahedron t opposite slot s, ordered so that t's fourth vertex is on its negative side.</summary>
        private void OutwardFace(int t, int s, out int a, out int b, out int c)
        {
            int v0 = _v[4 * t], v1 = _v[4 * t + 1], v2 = _v[4 * t + 2], v3 = _v[4 * t + 3];
            // The positively oriented (v0, v1, v2, v3) with v_s replaced by an outside point stays positive after one swap.
            if (s == 0) { a = v1; b = v2; c = v3; }
            else if (s == 1) { a = v0; b = v3; c = v2; }
            else if (s == 2) { a = v0; b = v1; c = v3; }
            else { a = v0; b = v2; c = v1; }
        }

        /// <summary>A tetrahedron containing p or, outside the hull, an infinite one whose face p lies beyond: a walk across
        /// the faces p lies beyond, from the last tetrahedron made; -1 when it does not end.</summary>
        private int Locate(int p)
        {
            int t = _last;
            if (!_alive[t]) for (t = 0; t < _count && !_alive[t]; t++) { }
            if (_v[4 * t + 3] == Infinite) t = _n[4 * t + 3];
            int limit = 4 * _count + 64;
            for (int step = 0; step < limit; step++)
            {
                if (_v[4 * t + 3] == Infinite) return t;
                int next = -1;
                for (int k = 0; k < 4 && next < 0; k++)
                {
                    int s = (k + step) & 3;  // rotating the first face tried keeps a walk from cycling
                    if (OrientWith(t, s, p) < 0) next = _n[4 * t + s];
                }
                if (next < 0) return t;
                t = next;
            }
            return -1;
        }

        /// <summary>The first live tetrahedron in conflict with p (a scan of all), or -1.</summary>
        private int AnyInConflict(int p)
        {
            for (int t = 0; t < _count; t++)
                if (_alive[t] && Conflict(t, p) == 1) return t;
            return -1;
        }

        /// <summary>+1: p is in conflict with tetrahedron t (its cavity), -1: not, 0: a true tie (p cospherical with t's
        /// corners in the lifted sense, which the tie heights exclude).</summary>
        private int Conflict(int t, int p)
        {
            int a = _v[4 * t], b = _v[4 * t + 1], c = _v[4 * t + 2], d = _v[4 * t + 3];
            if (d != Infinite)
            {
                double power = Power(a, b, c, d, p);
                return -(double.IsNaN(power) ? ExactPredicates.Power(_local, _height, _global[a], _global[b], _global[c], _global[d], _global[p]) : Math.Sign(power));
            }
            int side = OrientSign(a, b, c, p);
            if (side != 0) return side;
            double inPlane = PowerInPlane(a, b, c, p);
            return double.IsNaN(inPlane) ? ExactPredicates.PowerInPlane(_local, _height, _global[a], _global[b], _global[c], _global[p]) : Math.Sign(inPlane);
        }

        /// <summary>The exact sign of det[b − a, c − a, d − a] of vertices: the double one where it is decided, 0 where every
        /// product of the expansion is 0 (points in one axis-aligned plane), else computed exactly.</summary>
        private int OrientSign(int a, int b, int c, int d)
        {
            double det = Orient(a, b, c, d, out bool decided, out double permanent);
            if (decided) return Math.Sign(det);
            if (permanent == 0.0) return 0;
            return ExactPredicates.Orient(_local, _global[a], _global[b], _global[c], _global[d]);
        }

        /// <summary>Orientation of t with the vertex in slot s replaced by p (negative: p beyond that face); plain double,
        /// for the walk only.</summary>
        private double OrientWith(int t, int s, int p)
        {
            int a = _v[4 * t], b = _v[4 * t + 1], c = _v[4 * t + 2], d = _v[4 * t + 3];
            if (s == 0) a = p;
            else if (s == 1) b = p;
            else if (s == 2) c = p;
            else d = p;
            return Orient(a, b, c, d, out _);
        }

        private bool PositivelyOriented(int t) => OrientSign(_v[4 * t], _v[4 * t + 1], _v[4 * t + 2], _v[4 * t + 3]) > 0;

        /// <summary>det[b − a, c − a, d − a] of vertices; decided when its magnitude exceeds the rounding bound.</summary>
        private double Orient(int a, int b, int c, int d, out bool decided) => Orient(a, b, c, d, out decided, out _);

        private double Orient(int a, int b, int c, int d, out bool decided, out double permanent)
        {
            int ga = 3 * _global[a], gb = 3 * _global[b], gc = 3 * _global[c], gd = 3 * _global[d];
            double ux = _local[gb] - _local[ga], uy = _local[gb + 1] - _local[ga + 1], uz = _local[gb + 2] - _local[ga + 2];
            double vx = _local[gc] - _local[ga], vy = _local[gc + 1] - _local[ga + 1], vz = _local[gc + 2] - _local[ga + 2];
            double wx = _local[gd] - _local[ga], wy = _local[gd + 1] - _local[ga + 1], wz = _local[gd + 2] - _local[ga + 2];
            double det = ux * (vy * wz - vz * wy) + uy * (vz * wx - vx * wz) + uz * (vx * wy - vy * wx);
            permanent = Math.Abs(ux) * (Math.Abs(vy * wz) + Math.Abs(vz * wy)) + Math.Abs(uy) * (Math.Abs(vz * wx) + Math.Abs(vx * wz)) +
                               Math.Abs(uz) * (Math.Abs(vx * wy) + Math.Abs(vy * wx));
            decided = Math.Abs(det) > UndecidedFraction * permanent;
            return det;
        }

        /// <summary>The lifted determinant of (a, b, c, d) about p: negative when p's lifted point lies below the hyperplane
        /// of the positively oriented (a, b, c, d)'s (p in its power sphere); NaN within rounding of 0 (then computed exactly).</summary>
        private double Power(int a, int b, int c, int d, int p)
        {
            var m = _matrix;
            int gp = _global[p];
            Row(m, 0, _global[a], gp);
            Row(m, 1, _global[b], gp);
            Row(m, 2, _global[c], gp);
            Row(m, 3, _global[d], gp);
            return Determinant4(m);
        }

        /// <summary>For p in the plane of infinite tetrahedron (a, b, c)'s face: positive when p lies inside the face's power
        /// circle (the lifted determinant of b − a, c − a, p − a and the face's normal); NaN within rounding of 0.</summary>
        private double PowerInPlane(int a, int b, int c, int p)
        {
            var m = _matrix;
            int ga = _global[a];
            Row(m, 0, _global[b], ga);
            Row(m, 1, _global[c], ga);
            Row(m, 2, _global[p], ga);
            m[12] = m[1] * m[6] - m[2] * m[5];
            m[13] = m[2] * m[4] - m[0] * m[6];
            m[14] = m[0] * m[5] - m[1] * m[4];
            m[15] = 0.0;
            return Determinant4(m);
        }

        /// <summary>Row r: point q about point o, lifted (|q − o|² plus the difference of their tie heights).</summary>
        private void Row(double[] m, int r, int q, int o)
        {
            double dx = _local[3 * q] - _local[3 * o], dy = _local[3 * q + 1] - _local[3 * o + 1], dz = _local[3 * q + 2] - _local[3 * o + 2];
            m[4 * r] = dx;
            m[4 * r + 1] = dy;
            m[4 * r + 2] = dz;
            m[4 * r + 3] = dx * dx + dy * dy + dz * dz + (_height[q] - _height[o]);
        }

        /// <summary>A 4 × 4 determinant (row-major) by cofactors along the first row; NaN when within the rounding bound.</summary>
        private static double Determinant4(double[] m)
        {
            double det = 0.0, permanent = 0.0;
            for (int col = 0; col < 4; col++)
            {
                int c0 = col == 0 ? 1 : 0, c1 = col <= 1 ? 2 : 1, c2 = col <= 2 ? 3 : 2;
                double minor = m[4 + c0] * (m[8 + c1] * m[12 + c2] - m[8 + c2] * m[12 + c1]) -
                               m[4 + c1] * (m[8 + c0] * m[12 + c2] - m[8 + c2] * m[12 + c0]) +
                               m[4 + c2] * (m[8 + c0] * m[12 + c1] - m[8 + c1] * m[12 + c0]);
                double absolute = Math.Abs(m[4 + c0]) * (Math.Abs(m[8 + c1] * m[12 + c2]) + Math.Abs(m[8 + c2] * m[12 + c1])) +
                                  Math.Abs(m[4 + c1]) * (Math.Abs(m[8 + c0] * m[12 + c2]) + Math.Abs(m[8 + c2] * m[12 + c0])) +
                                  Math.Abs(m[4 + c2]) * (Math.Abs(m[8 + c0] * m[12 + c1]) + Math.Abs(m[8 + c1] * m[12 + c0]));
                det += (col % 2 == 0 ? 1 : -1) * m[col] * minor;
                permanent += Math.Abs(m[col]) * absolute;
            }
            return Math.Abs(det) > UndecidedFraction * permanent ? det : double.NaN;
        }

        private int Allocate()
        {
            int t;
            if (_free.Count > 0) t = _free.Pop();
            else
            {
                if (_count == _alive.Length)
                {
                    int size = Math.Max(64, 2 * _alive.Length);
                    Array.Resize(ref _v, 4 * size);
                    Array.Resize(ref _n, 4 * size);
                    Array.Resize(ref _alive, size);
                }
                t = _count++;
            }
            _alive[t] = true;
            return t;
        }

        /// <summary>The slot of <paramref name="t"/> whose neighbour is <paramref name="neighbour"/>, or -1.</summary>
        private int SlotOf(int t, int neighbour)
        {
            for (int s = 0; s < 4; s++)
                if (_n[4 * t + s] == neighbour) return s;
            return -1;
        }

        /// <summary>The three vertices of t other than slot s, sorted and packed (21 bits each).</summary>
        private static long FaceKey(int[] v, int t, int s)
        {
            int a = v[4 * t + (s == 0 ? 1 : 0)], b = v[4 * t + (s <= 1 ? 2 : 1)], c = v[4 * t + (s <= 2 ? 3 : 2)];
            var key = new TriangleKey(a, b, c);
            return ((long)key.A << 42) | ((long)key.B << 21) | (long)(uint)key.C;
        }

        /// <summary>The two vertices of t other than slots i and j (one may be the infinite vertex), sorted and packed.</summary>
        private static long EdgeKey(int[] v, int t, int i, int j)
        {
            int x = -2, y = -2;
            for (int s = 0; s < 4; s++)
            {
                if (s == i || s == j) continue;
                if (x == -2) x = v[4 * t + s];
                else y = v[4 * t + s];
            }
            int lo = Math.Min(x, y) + 1, hi = Math.Max(x, y) + 1;
            return ((long)lo << 32) | (long)(uint)hi;
        }
    }
}
