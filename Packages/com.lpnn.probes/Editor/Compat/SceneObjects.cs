using UnityEngine;

namespace Lpnn.Probes.Editor
{
    /// <summary>Every loaded active object of a type, unsorted, with the overload each Unity version wants
    /// (UnityCsReference Runtime/Export/Scripting/UnityEngineObject.bindings.cs): FindObjectsByType&lt;T&gt;(FindObjectsSortMode)
    /// since 2022.2; from 6000.4 that overload is [Obsolete] ("previous sort order cannot be maintained") and the
    /// parameterless FindObjectsByType&lt;T&gt;() replaces it.</summary>
    internal static class SceneObjects
    {
        public static T[] FindAll<T>() where T : Object
        {
#if UNITY_6000_4_OR_NEWER
            return Object.FindObjectsByType<T>();
#else
            return Object.FindObjectsByType<T>(FindObjectsSortMode.None);
#endif
        }
    }
}
