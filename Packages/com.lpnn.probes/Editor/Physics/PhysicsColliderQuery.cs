using System.Collections.Generic;
using Lpnn.Probes.Core.Features;
using Unity.Collections;
using UnityEngine;
using UnityEngine.SceneManagement;
using NumericsVector3 = System.Numerics.Vector3;

namespace Lpnn.Probes.Editor
{
    /// <summary>The core's IColliderQuery on Unity physics, for Core.Features.InsideColliders (which decides; this only asks):
    /// one batched OverlapSphereCommand job per call in the volume's physics scene, ignoring triggers and the Ignore Raycast
    /// layer as the validity rays do (UnityCsReference 2022.3 … 6000.7 Modules/Physics/ScriptBindings/QueryCommand.bindings.cs:
    /// OverlapSphereCommand(PhysicsScene, Vector3, float, QueryParameters), ScheduleBatch(..., maxHits), ColliderHit.collider,
    /// "a main-thread only API", read after Complete). Collider.ClosestPoint (Dynamics.bindings.cs 2022.3, Collider.bindings.cs
    /// 6000.x) confirms containment for the shapes it supports. Call inside a <see cref="RaycastScope"/>, as the rays are: the
    /// volume's own colliders are disabled there and transforms synced. Compiled against the API surfaces only; it has not run
    /// in a Unity editor.</summary>
    internal sealed class PhysicsColliderQuery : IColliderQuery
    {
        private const int MinCommandsPerJob = 256;
        private readonly PhysicsScene _physics;
        /// <summary>Handle h is _colliders[h - 1]; valid until the next Overlap.</summary>
        private readonly List<Collider> _colliders = new List<Collider>();
        private readonly Dictionary<Collider, int> _handles = new Dictionary<Collider, int>();

        /// <summary>Queries the physics scene of <paramref name="scene"/> (the volume's: a Prefab Mode stage has its own, see
        /// <see cref="PhysicsRaycaster"/>).</summary>
        public PhysicsColliderQuery(Scene scene)
        {
            _physics = scene.GetPhysicsScene();
        }

        public void Overlap(NumericsVector3[] points, float radius, int maxHits, int[] colliders)
        {
            _colliders.Clear();
            _handles.Clear();
            int count = points.Length;
            var query = new QueryParameters(Physics.DefaultRaycastLayers, false, QueryTriggerInteraction.Ignore, false);
            var commands = new NativeArray<OverlapSphereCommand>(count, Allocator.TempJob);
            var hits = new NativeArray<ColliderHit>(count * maxHits, Allocator.TempJob);
            try
            {
                for (int p = 0; p < count; p++)
                    commands[p] = new OverlapSphereCommand(_physics, points[p].ToUnity(), radius, query);
                OverlapSphereCommand.ScheduleBatch(commands, hits, MinCommandsPerJob, maxHits).Complete();
                for (int slot = 0; slot < count * maxHits; slot++)
                {
                    // An empty slot resolves to no object (instance / entity id 0).
                    var collider = hits[slot].collider;
                    if (collider == null)
                    {
                        colliders[slot] = 0;
                        continue;
                    }
                    if (!_handles.TryGetValue(collider, out int handle))
                    {
                        _colliders.Add(collider);
                        handle = _colliders.Count;
                        _handles[collider] = handle;
                    }
                    colliders[slot] = handle;
                }
            }
            finally
            {
                commands.Dispose();
                hits.Dispose();
            }
        }

        public ColliderShape ShapeOf(int collider)
        {
            var c = _colliders[collider - 1];
            if (c is BoxCollider) return ColliderShape.Box;
            if (c is SphereCollider) return ColliderShape.Sphere;
            if (c is CapsuleCollider) return ColliderShape.Capsule;
            if (c is MeshCollider mesh) return mesh.convex ? ColliderShape.ConvexMesh : ColliderShape.TriangleMesh;
            if (c is TerrainCollider) return ColliderShape.Heightfield;
            return ColliderShape.Other;
        }

        public NumericsVector3 ClosestPoint(int collider, NumericsVector3 point) =>
            _colliders[collider - 1].ClosestPoint(point.ToUnity()).ToNumerics();
    }
}
