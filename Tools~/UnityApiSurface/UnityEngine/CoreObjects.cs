// Stand-ins for UnityEngine object model members used by LPNN (signatures only; see ../README.md).
using System;
using System.Collections.Generic;

namespace UnityEngine
{
    // UnityCsReference 2022.3 Runtime/Export/Scripting/UnityEngineObject.bindings.cs
    [Flags]
    public enum HideFlags { None = 0, HideInHierarchy = 1, HideInInspector = 2, DontSaveInEditor = 4, NotEditable = 8, DontSaveInBuild = 16, DontUnloadUnusedAsset = 32, DontSave = 52, HideAndDontSave = 61 }

    // UnityCsReference 2022.3 Runtime/Export/Scripting/UnityEngineObject.bindings.cs
    public enum FindObjectsSortMode { None = 0, InstanceID = 1 }

    // UnityCsReference 2022.3 Runtime/Export/Scripting/UnityEngineObject.bindings.cs
    public class Object
    {
        public string name { get { throw null; } set { } }
        public HideFlags hideFlags { get { throw null; } set { } }
        public int GetInstanceID() { throw null; }
        public static void DestroyImmediate(Object obj) { }
        public static T[] FindObjectsByType<T>(FindObjectsSortMode sortMode) where T : Object { throw null; }
        public static implicit operator bool(Object exists) { throw null; }
        public static bool operator ==(Object x, Object y) { throw null; }
        public static bool operator !=(Object x, Object y) { throw null; }
        public override bool Equals(object other) { throw null; }
        public override int GetHashCode() { throw null; }
    }

    // UnityCsReference 2022.3 Runtime/Export/Scripting/Component.bindings.cs
    public class Component : Object
    {
        public Transform transform { get { throw null; } }
        public GameObject gameObject { get { throw null; } }
        public T GetComponent<T>() { throw null; }
        public T[] GetComponentsInChildren<T>() { throw null; }
    }

    // UnityCsReference 2022.3 Runtime/Export/Scripting/Behaviour.bindings.cs
    public class Behaviour : Component
    {
        public bool enabled { get { throw null; } set { } }
    }

    // UnityCsReference 2022.3 Runtime/Export/Scripting/MonoBehaviour.bindings.cs
    public class MonoBehaviour : Behaviour { }

    // UnityCsReference 2022.3 Runtime/Export/Scripting/ScriptableObject.bindings.cs
    public class ScriptableObject : Object { }

    // UnityCsReference 2022.3 Runtime/Export/BaseClass.cs
    public enum PrimitiveType { Sphere = 0, Capsule = 1, Cylinder = 2, Cube = 3, Plane = 4, Quad = 5 }

    // UnityCsReference 2022.3 Runtime/Export/Scripting/GameObject.bindings.cs
    public sealed class GameObject : Object
    {
        public GameObject(string name) { }
        public static GameObject CreatePrimitive(PrimitiveType type) { throw null; }
        public static GameObject Find(string name) { throw null; }
        public T AddComponent<T>() where T : Component { throw null; }
        public T GetComponent<T>() { throw null; }
        public Transform transform { get { throw null; } }
        public bool activeInHierarchy { get { throw null; } }
        public SceneManagement.Scene scene { get { throw null; } }
    }

    // UnityCsReference 2022.3 Runtime/Transform/ScriptBindings/Transform.bindings.cs
    public class Transform : Component
    {
        public Vector3 position { get { throw null; } set { } }
        public Quaternion rotation { get { throw null; } set { } }
        public Vector3 localPosition { get { throw null; } set { } }
        public Vector3 localScale { get { throw null; } set { } }
        public Transform parent { get { throw null; } set { } }
        public Matrix4x4 localToWorldMatrix { get { throw null; } }
        public Matrix4x4 worldToLocalMatrix { get { throw null; } }
        public void SetParent(Transform parent, bool worldPositionStays) { }
        public void SetPositionAndRotation(Vector3 position, Quaternion rotation) { }
        public Vector3 TransformPoint(Vector3 position) { throw null; }
    }

    // UnityCsReference 2022.3 Runtime/Export/Scripting/TextAsset.cs
    public class TextAsset : Object
    {
        public TextAsset(string text) { }
        public string text { get { throw null; } }
    }

    // UnityCsReference 2022.3 Runtime/Export/Debug/Debug.bindings.cs
    public static class Debug
    {
        public static void Log(object message) { }
        public static void LogWarning(object message) { }
        public static void LogWarning(object message, Object context) { }
        public static void LogError(object message) { }
        public static void LogError(object message, Object context) { }
        public static void LogException(Exception exception) { }
        public static void LogException(Exception exception, Object context) { }
    }

    // UnityCsReference 2022.3 Runtime/Export/Application/Application.bindings.cs
    public class Application
    {
        public static bool isBatchMode { get { throw null; } }
        public static string dataPath { get { throw null; } }
        public static string unityVersion { get { throw null; } }
    }

    // UnityCsReference 2022.3 Runtime/Export/SystemInfo/SystemInfo.bindings.cs
    public sealed class SystemInfo
    {
        public static bool supportsComputeShaders { get { throw null; } }
    }

    // UnityCsReference 2022.3 Runtime/Export/Serialization/Serialization.cs
    [AttributeUsage(AttributeTargets.Field, Inherited = true, AllowMultiple = false)]
    public sealed class SerializeField : Attribute { }

    // UnityCsReference 2022.3 Runtime/Export/Scripting/Attributes.cs
    [AttributeUsage(AttributeTargets.Field, Inherited = true, AllowMultiple = false)]
    public sealed class HideInInspector : Attribute { }

    // UnityCsReference 2022.3 Runtime/Export/Scripting/Attributes.cs
    [AttributeUsage(AttributeTargets.Class, AllowMultiple = false)]
    public sealed class AddComponentMenu : Attribute
    {
        public AddComponentMenu(string menuName) { }
    }

    // UnityCsReference 2022.3 Runtime/Export/Scripting/Attributes.cs
    [AttributeUsage(AttributeTargets.Class, Inherited = false, AllowMultiple = false)]
    public sealed class DisallowMultipleComponent : Attribute { }

    // UnityCsReference 2022.3 Runtime/Export/PropertyDrawer/PropertyAttribute.cs
    [AttributeUsage(AttributeTargets.Field, Inherited = true, AllowMultiple = false)]
    public abstract class PropertyAttribute : Attribute { }

    // UnityCsReference 2022.3 Runtime/Export/PropertyDrawer/PropertyAttribute.cs
    public class TooltipAttribute : PropertyAttribute
    {
        public TooltipAttribute(string tooltip) { }
    }

    // UnityCsReference 2022.3 Runtime/Export/PropertyDrawer/PropertyAttribute.cs
    public sealed class RangeAttribute : PropertyAttribute
    {
        public RangeAttribute(float min, float max) { }
    }
}

namespace UnityEngine.SceneManagement
{
    // UnityCsReference 2022.3 Runtime/Export/SceneManager/Scene.bindings.cs
    public struct Scene
    {
        public string path { get { throw null; } }
        public string name { get { throw null; } }
    }
}
