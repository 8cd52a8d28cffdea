using System;
using Lpnn.Probes.Core.Features;
using Unity.Collections;
using UnityEngine;
using UnityEngine.SceneManagement;
using NumericsVector3 = System.Numerics.Vector3;

namespace Lpnn.Probes.Editor
{
    /// <summary>The core's IRaycaster on Unity physics, each ray ending at its own distance when asked
    /// (IPerRayDistanceRaycaster): one batched RaycastCommand job per call, hitting faces of either
    /// side (QueryParameters.hitBackfaces) and ignoring triggers (UnityCsReference 2022.3
    /// Modules/Physics/ScriptBindings/QueryCommand.bindings.cs; 6000.0 same file). Call inside a <see cref="RaycastScope"/>
    /// so transforms are synced and the volume's own colliders are out of the way. The probe-validity rule reads the hit
    /// normal's orientation: on a back-face hit PhysX reports the triangle's winding normal, turning it toward the ray only
    /// for meshes flagged double-sided (NVIDIAGameWorks/PhysX physx/source/geomutils/src/mesh/GuMidphaseBV4.cpp,
    /// raycast_triangleMesh_BV4), which MeshCollider does not set (Documentation~/features.md "Probe validity").</summary>
    internal sealed class PhysicsRaycaster : IPerRayDistanceRaycaster
    {
        private const int MinCommandsPerJob = 256;
        private readonly PhysicsScene _physics;

        /// <summary>Casts in the physics scene of <paramref name="scene"/> (the volume's). A Prefab Mode stage is a preview
        /// scene with its own physics scene (UnityCsReference 6000.0 Editor/Mono/SceneManagement/StageManager/PrefabStage/
        /// PrefabStage.cs: EditorSceneManager.NewPreviewScene), so the RaycastCommand constructor without a PhysicsScene,
        /// which queries Physics.defaultPhysicsScene, would see none of the prefab's colliders there: every point valid,
        /// every occlusion feature zero (issue 31). Scene.GetPhysicsScene and RaycastCommand(PhysicsScene, ...): 2022.3
        /// Modules/Physics/ScriptBindings/Dynamics.bindings.cs, QueryCommand.bindings.cs; 6000.x PhysicsScene.bindings.cs.</summary>
        public PhysicsRaycaster(Scene scene)
        {
            _physics = scene.GetPhysicsScene();
        }

        public void Cast(NumericsVector3[] origins, NumericsVector3[] directions, float maxDistance, RayHit[] results) =>
            CastEach(origins, directions, maxDistance, null, results);

        /// <summary>Each ray up to its own distance (the segment test casts each segment to its length): a RaycastCommand
        /// carries its own distance, the constructor's last argument (UnityCsReference 2022.3 and 6000.x
        /// Modules/Physics/ScriptBindings/QueryCommand.bindings.cs, RaycastCommand(PhysicsScene, Vector3 from, Vector3
        /// direction, QueryParameters, float distance)).</summary>
        public void Cast(NumericsVector3[] origins, NumericsVector3[] directions, float[] maxDistances, RayHit[] results)
        {
            // null would mean "one distance for all" to CastEach, here 0: every ray a miss
            if (maxDistances == null) throw new ArgumentNullException(nameof(maxDistances));
            CastEach(origins, directions, 0, maxDistances, results);
        }

        /// <summary>Ray n up to maxDistances[n], or up to <paramref name="maxDistance"/> when maxDistances is null.</summary>
        private void CastEach(NumericsVector3[] origins, NumericsVector3[] directions, float maxDistance, float[] maxDistances, RayHit[] results)
        {
            int count = origins.Length;
            var query = new QueryParameters(Physics.DefaultRaycastLayers, false, QueryTriggerInteraction.Ignore, true);
            // Plain locals + finally rather than `using`: elements are written, and C# forbids writing into a struct using-variable.
            var commands = new NativeArray<RaycastCommand>(count, Allocator.TempJob);
            var hits = new NativeArray<RaycastHit>(count, Allocator.TempJob);
            try
            {
                for (int r = 0; r < count; r++)
                    commands[r] = new RaycastCommand(_physics, origins[r].ToUnity(), directions[r].ToUnity(), query,
                        maxDistances == null ? maxDistance : maxDistances[r]);
                RaycastCommand.ScheduleBatch(commands, hits, MinCommandsPerJob, 1).Complete();
                for (int r = 0; r < count; r++)
                {
                    var hit = hits[r];
                    // An empty result slot has collider id 0 (UnityCsReference Modules/Physics/ScriptBindings/RaycastHit.bindings.cs):
                    // colliderEntityId from 6000.3, where colliderInstanceID becomes [Obsolete] (an error from 6000.5).
#if UNITY_6000_3_OR_NEWER
                    results[r] = hit.colliderEntityId == EntityId.None
#else
                    results[r] = hit.colliderInstanceID == 0
#endif
                        ? RayHit.Miss
                        : new RayHit { Distance = hit.distance, Normal = hit.normal.ToNumerics() };
                }
            }
            finally
            {
                commands.Dispose();
                hits.Dispose();
            }
        }
    }
}
