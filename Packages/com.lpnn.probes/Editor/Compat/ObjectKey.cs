using System;
using UnityEngine;
using Object = UnityEngine.Object;

namespace Lpnn.Probes.Editor
{
    /// <summary>A dictionary key for a live Unity object (one session or gizmo cache per volume) on every supported Unity.
    /// UnityCsReference Runtime/Export/Scripting/UnityEngineObject.bindings.cs: 6000.3 adds Object.GetEntityId() and the
    /// EntityId struct (IEquatable); 6000.4 marks Object.GetInstanceID() [Obsolete] and 6000.5 [Obsolete(..., true)],
    /// a compile error. The object itself is no key: Object.Equals treats every destroyed object as equal to null.</summary>
    internal readonly struct ObjectKey : IEquatable<ObjectKey>
    {
#if UNITY_6000_3_OR_NEWER
        private readonly EntityId _id;
        private ObjectKey(EntityId id) { _id = id; }
        public static ObjectKey Of(Object target) => new ObjectKey(target.GetEntityId());
#else
        private readonly int _id;
        private ObjectKey(int id) { _id = id; }
        public static ObjectKey Of(Object target) => new ObjectKey(target.GetInstanceID());
#endif

        public bool Equals(ObjectKey other) => _id.Equals(other._id);
        public override bool Equals(object obj) => obj is ObjectKey other && Equals(other);
        public override int GetHashCode() => _id.GetHashCode();
    }
}
