// Stand-ins for UnityEngine.PhysicsModule members used by LPNN (signatures only; see ../README.md).
using Unity.Collections;
using Unity.Jobs;

namespace UnityEngine
{
    // UnityCsReference 2022.3 Modules/Physics/Managed/Dynamics.cs
    public enum QueryTriggerInteraction { UseGlobal = 0, Ignore = 1, Collide = 2 }

    // UnityCsReference 2022.3 Modules/Physics/ScriptBindings/Dynamics.bindings.cs (6000.0: Physics.bindings.cs)
    public class Physics
    {
        public const int DefaultRaycastLayers = ~4;
        public static void SyncTransforms() { }
    }

    // UnityCsReference 2022.3 Modules/Physics/ScriptBindings/Dynamics.bindings.cs (6000.0: Collider.bindings.cs)
    public class Collider : Component
    {
        public bool enabled { get { throw null; } set { } }
    }

    // UnityCsReference 2022.3 Modules/Physics/ScriptBindings/Dynamics.bindings.cs (6000.0: MeshCollider.bindings.cs)
    public class MeshCollider : Collider
    {
        public Mesh sharedMesh { get { throw null; } set { } }
    }

    // UnityCsReference 2022.3 Modules/Physics/ScriptBindings/Dynamics.bindings.cs (6000.0: RaycastHit.bindings.cs)
    public struct RaycastHit
    {
        public int colliderInstanceID { get { throw null; } }
        public Vector3 normal { get { throw null; } set { } }
        public float distance { get { throw null; } set { } }
    }

    // UnityCsReference 2022.3 Modules/Physics/ScriptBindings/QueryCommand.bindings.cs (QueryParameters since 2022.2; 6000.0 same)
    public struct QueryParameters
    {
        public QueryParameters(int layerMask = Physics.DefaultRaycastLayers, bool hitMultipleFaces = false,
            QueryTriggerInteraction hitTriggers = QueryTriggerInteraction.UseGlobal, bool hitBackfaces = false) { throw null; }
    }

    // UnityCsReference 2022.3 Modules/Physics/ScriptBindings/QueryCommand.bindings.cs (6000.0 same)
    public struct RaycastCommand
    {
        public RaycastCommand(Vector3 from, Vector3 direction, QueryParameters queryParameters, float distance = float.MaxValue) { throw null; }
        public static JobHandle ScheduleBatch(NativeArray<RaycastCommand> commands, NativeArray<RaycastHit> results, int minCommandsPerJob,
            int maxHits, JobHandle dependsOn = new JobHandle()) { throw null; }
    }
}
