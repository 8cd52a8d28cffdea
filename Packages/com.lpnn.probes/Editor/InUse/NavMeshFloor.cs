using Lpnn.Probes.Core.InUse;
using UnityEngine.AI;
using NumericsVector3 = System.Numerics.Vector3;

namespace Lpnn.Probes.Editor
{
    /// <summary>The scene's baked NavMesh as the in-use rule's floor (Documentation~/in-use.md, "Sources" of
    /// Documentation~/index.md): its triangles, from NavMesh.CalculateTriangulation, hit by the rule's straight-down floor
    /// rays (Core TriangleFloorRaycaster). Chosen over NavMesh.SamplePosition, which finds the nearest NavMesh point within a
    /// sphere, one native call per point: not the floor below a point, and a million calls on large volumes. The
    /// triangulation covers every loaded NavMesh (all agent types, NavMeshSurface components included), in world space.</summary>
    internal static class NavMeshFloor
    {
        /// <summary>The baked NavMesh's triangles as a floor raycaster, or null when the scene has no NavMesh.</summary>
        public static TriangleFloorRaycaster Baked()
        {
            // NavMesh.CalculateTriangulation and NavMeshTriangulation.vertices/indices: UnityCsReference
            // Modules/AI/NavMesh/NavMesh.bindings.cs (2022.3: lines 43-46, 257; 6000.0 and 6000.3: 43-46, 244; 6000.5 and 6000.7:
            // 44-47, 246). Empty arrays when nothing is baked.
            var triangulation = NavMesh.CalculateTriangulation();
            var vertices = triangulation.vertices;
            var indices = triangulation.indices;
            if (vertices == null || indices == null || indices.Length < 3) return null;
            var positions = new NumericsVector3[vertices.Length];
            for (int v = 0; v < vertices.Length; v++) positions[v] = vertices[v].ToNumerics();
            return new TriangleFloorRaycaster(positions, indices);
        }
    }
}
