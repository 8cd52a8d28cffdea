using System.Numerics;

namespace Lpnn.Probes.Core.Features
{
    /// <summary>What a collider is, as far as <see cref="InsideColliders"/> reads an overlap with it: whether the physics engine
    /// treats it as a solid volume (a point inside overlaps it) or as a surface (only a point near its triangles does).</summary>
    internal enum ColliderShape
    {
        /// <summary>Anything else (CharacterController, WheelCollider, a type this package does not know): never read as solid.</summary>
        Other = 0,
        Box,
        Sphere,
        Capsule,
        /// <summary>A MeshCollider with <c>convex</c> on: PhysX cooks a convex hull, a solid.</summary>
        ConvexMesh,
        /// <summary>A MeshCollider with <c>convex</c> off: PhysX tests its triangles only, so a point inside a closed mesh
        /// overlaps nothing; the back-face rays (<see cref="ProbeValidity"/>) see it from inside instead.</summary>
        TriangleMesh,
        /// <summary>A TerrainCollider: a PhysX height field, solid below its surface for overlaps.</summary>
        Heightfield,
    }

    /// <summary>Overlap queries against the scene's colliders (Unity: OverlapSphereCommand in the volume's physics scene,
    /// Collider.ClosestPoint; tests: analytic shapes). The engine-side half of <see cref="InsideColliders"/>, which holds the
    /// decisions: which shapes count as solid, and how "inside" is confirmed.</summary>
    internal interface IColliderQuery
    {
        /// <summary>For each point, up to <paramref name="maxHits"/> colliders that a sphere of <paramref name="radius"/> around it
        /// overlaps (triggers and the volume's own colliders excluded, as for the rays), as handles ≥ 1 written into
        /// <c>colliders[p · maxHits + h]</c>; unused slots are 0. A handle is valid until the next call.</summary>
        void Overlap(Vector3[] points, float radius, int maxHits, int[] colliders);

        /// <summary>The shape of the collider behind a handle of the last <see cref="Overlap"/>.</summary>
        ColliderShape ShapeOf(int collider);

        /// <summary>The point of the collider closest to <paramref name="point"/>: <paramref name="point"/> itself when it is
        /// inside the collider or exactly on its boundary. Only asked for Box, Sphere, Capsule and ConvexMesh.</summary>
        Vector3 ClosestPoint(int collider, Vector3 point);
    }
}
