using System;
using System.Numerics;
using System.Threading;
using Lpnn.Probes.Core.Grid;

namespace Lpnn.Probes.Core.Features
{
    /// <summary>Which evaluation points lie inside a solid collider — the case the back-face rays of <see cref="ProbeValidity"/>
    /// cannot see (Documentation~/features.md "Probe validity": points inside solid colliders). A ray that starts inside a
    /// box, sphere, capsule or convex collider does not report it (Unity Scripting Reference, Physics.Raycast; PhysX
    /// reports such a hit at distance 0 with the normal against the ray, a front face by the rule's reading, so it would
    /// not count either: NVIDIAGameWorks/PhysX physx/source/geomutils/src/GuRaycastTests.cpp raycast_box, raycast_sphere,
    /// and the convex raycast's "ray starts inside convex"). So the Corridor sample's BoxCollider walls never made a point
    /// invalid.
    ///
    /// The rule, decided from the sources (facts, cited where they are used):
    /// 1. A sphere of <see cref="QueryRadius"/> (a thousandth of a cell) around the point is overlapped against the scene's
    ///    colliders, as the rays are (triggers ignored, the volume's own colliders disabled): Unity's OverlapSphereCommand
    ///    (UnityCsReference 2022.3 … 6000.7 Modules/Physics/ScriptBindings/QueryCommand.bindings.cs).
    /// 2. A box, sphere, capsule or convex mesh it overlaps contains the point when the collider's closest point to it is
    ///    the point itself: Collider.ClosestPoint returns the input location when it is inside the collider or exactly on
    ///    its boundary, and supports only those four shapes (Scripting Reference, Physics.ClosestPoint / Collider.ClosestPoint;
    ///    the binding is extern: UnityCsReference Modules/Physics/ScriptBindings/Dynamics.bindings.cs 2022.3,
    ///    Collider.bindings.cs 6000.x). On the boundary counts as inside: PhysX defines its objects as closed
    ///    (GuOverlapTests.cpp, GeomOverlapCallback_SpherePlane).
    /// 3. A height field (TerrainCollider) it overlaps contains the point: PhysX's sphere–height-field overlap is true
    ///    when the sphere's centre is below the surface (physx/source/geomutils/src/hf/GuOverlapTestsHF.cpp
    ///    intersectHeightFieldSphere), so the point is below the terrain or within the query radius above it.
    ///    Collider.ClosestPoint does not support terrain, so the overlap decides.
    /// 4. A non-convex MeshCollider never contains a point here: PhysX overlaps a sphere against its triangles only
    ///    (physx/source/geomutils/src/mesh/GuOverlapTestsMesh.cpp GeomOverlapCallback_SphereMesh → intersectSphereVsMesh),
    ///    so an overlap only says the point is within the radius of its surface, and a point inside a closed mesh
    ///    overlaps nothing. The back-face rays already see such meshes from inside (hitBackfaces).
    /// 5. Any other collider (CharacterController, WheelCollider, …) is not read as solid.
    /// A point found inside gets back-face fraction <see cref="ProbeValidity.InsideColliderFraction"/> (1: as if the
    /// primitive were the closed triangle mesh Python's importer sees, every ray leaving through it from behind), so
    /// every reader of the fractions — selection, scoring, captures, <c>lpnn place</c> — treats it as invalid.</summary>
    internal static class InsideColliders
    {
        public const string Stage = "finding points inside colliders";

        /// <summary>The overlap sphere's radius in cells: small enough that "within the radius above a terrain" is inside
        /// the terrain to a thousandth of a cell, large enough to stay far above float precision at level scale.</summary>
        public const double RadiusCells = 1e-3;

        /// <summary>Colliders read per point: a point touching more solids than this is inside one of them in practice
        /// (the first eight are read; a miss only leaves the point to the rays).</summary>
        public const int MaxHitsPerPoint = 8;

        private const int PointsPerBatch = 4096;

        /// <summary>The overlap sphere's radius for a grid of this cell size (metres).</summary>
        public static float QueryRadius(double cellSize)
        {
            if (!(cellSize > 0) || double.IsInfinity(cellSize)) throw new ArgumentOutOfRangeException(nameof(cellSize), cellSize, "the cell size must be finite and > 0");
            return (float)(RadiusCells * cellSize);
        }

        /// <summary>Whether a collider of this shape, overlapped by the query sphere at <paramref name="point"/>, contains the point
        /// (the rule's steps 2–5); <paramref name="closestPoint"/> is asked only for the shapes that support it.</summary>
        public static bool Contains(ColliderShape shape, Vector3 point, Func<Vector3> closestPoint)
        {
            switch (shape)
            {
                case ColliderShape.Box:
                case ColliderShape.Sphere:
                case ColliderShape.Capsule:
                case ColliderShape.ConvexMesh:
                    return IsSamePoint(closestPoint(), point);
                case ColliderShape.Heightfield:
                    return true;
                default:
                    return false;
            }
        }

        /// <summary>True when Collider.ClosestPoint handed the point back (it returns the input location for a point inside or
        /// on the boundary); a float round trip through the collider's local space is allowed a few ulps at the point's
        /// magnitude, far below any distance that matters.</summary>
        public static bool IsSamePoint(Vector3 closest, Vector3 point)
        {
            float scale = Math.Max(1f, Math.Max(Math.Abs(point.X), Math.Max(Math.Abs(point.Y), Math.Abs(point.Z))));
            float tolerance = 1e-6f * scale;
            return Math.Abs(closest.X - point.X) <= tolerance && Math.Abs(closest.Y - point.Y) <= tolerance && Math.Abs(closest.Z - point.Z) <= tolerance;
        }

        /// <summary>One flag per grid point: true inside (or on) a solid collider. In batches, with progress and cancel between them.</summary>
        public static bool[] Find(EvaluationGrid grid, IColliderQuery query, ProgressCallback progress = null, CancellationToken cancel = default)
        {
            if (grid == null) throw new ArgumentNullException(nameof(grid));
            return Find(grid.Count, grid.GetPosition, grid.CellSize, query, progress, cancel);
        }

        /// <summary>One flag per point of <paramref name="position"/> (0 ≤ n &lt; <paramref name="count"/>), queried with the radius of
        /// a grid of <paramref name="cellSize"/>.</summary>
        public static bool[] Find(int count, Func<int, Vector3> position, double cellSize, IColliderQuery query, ProgressCallback progress = null,
            CancellationToken cancel = default)
        {
            if (position == null) throw new ArgumentNullException(nameof(position));
            if (query == null) throw new ArgumentNullException(nameof(query));
            if (count < 0) throw new ArgumentOutOfRangeException(nameof(count), count, "a count of points is ≥ 0");
            float radius = QueryRadius(cellSize);
            var inside = new bool[count];
            int batch = Math.Min(PointsPerBatch, count);
            var points = new Vector3[batch];
            var colliders = new int[batch * MaxHitsPerPoint];
            for (int first = 0; first < count; first += batch)
            {
                // The editor reads its cancel button in the progress callback: check right after it.
                progress?.Invoke(Stage, first, count);
                cancel.ThrowIfCancellationRequested();
                int inBatch = Math.Min(batch, count - first);
                if (inBatch != points.Length)
                {
                    points = new Vector3[inBatch];
                    colliders = new int[inBatch * MaxHitsPerPoint];
                }
                for (int p = 0; p < inBatch; p++) points[p] = position(first + p);
                Array.Clear(colliders, 0, colliders.Length);
                query.Overlap(points, radius, MaxHitsPerPoint, colliders);
                for (int p = 0; p < inBatch; p++)
                {
                    var point = points[p];
                    for (int h = 0; h < MaxHitsPerPoint; h++)
                    {
                        int collider = colliders[p * MaxHitsPerPoint + h];
                        if (collider == 0) continue;
                        if (collider < 0) throw new FeatureException("the collider query returned handle " + collider + " for point " + (first + p) + "; handles are ≥ 1 (0: none)");
                        if (!Contains(query.ShapeOf(collider), point, () => query.ClosestPoint(collider, point))) continue;
                        inside[first + p] = true;
                        break;
                    }
                }
            }
            progress?.Invoke(Stage, count, count);
            cancel.ThrowIfCancellationRequested();
            return inside;
        }
    }
}
