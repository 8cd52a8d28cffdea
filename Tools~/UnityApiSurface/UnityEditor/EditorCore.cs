// Stand-ins for UnityEditor members used by LPNN (signatures only; see ../README.md).
using System;
using UnityEngine;
using Object = UnityEngine.Object;

namespace UnityEditor
{
    // UnityCsReference 2022.3 Editor/Mono/Inspector/CustomEditor.cs
    [AttributeUsage(AttributeTargets.Class, AllowMultiple = true, Inherited = false)]
    public class CustomEditor : Attribute
    {
        public CustomEditor(Type inspectedType) { }
    }

    // UnityCsReference 2022.3 Editor/Mono/Inspector/Editor.cs
    public class Editor : ScriptableObject
    {
        public Object target { get { throw null; } set { } }
        public SerializedObject serializedObject { get { throw null; } }
        public virtual void OnInspectorGUI() { }
    }

    // UnityCsReference 2022.3 Editor/Mono/SerializedObject.bindings.cs
    public class SerializedObject : IDisposable
    {
        public void Update() { }
        public bool ApplyModifiedProperties() { throw null; }
        public SerializedProperty FindProperty(string propertyPath) { throw null; }
        public void Dispose() { }
    }

    // UnityCsReference 2022.3 Editor/Mono/SerializedProperty.bindings.cs
    public class SerializedProperty : IDisposable
    {
        public int arraySize { get { throw null; } set { } }
        public SerializedProperty GetArrayElementAtIndex(int index) { throw null; }
        public SerializedProperty FindPropertyRelative(string relativePropertyPath) { throw null; }
        public Vector3 vector3Value { get { throw null; } set { } }
        public int enumValueIndex { get { throw null; } set { } }
        public string stringValue { get { throw null; } set { } }
        public void Dispose() { }
    }

    // UnityCsReference 2022.3 Editor/Mono/EditorGUIUtility.bindings.cs
    public enum MessageType { None = 0, Info = 1, Warning = 2, Error = 3 }

    // UnityCsReference 2022.3 Editor/Mono/EditorGUI.cs
    public sealed partial class EditorGUI
    {
        public static void BeginChangeCheck() { }
        public static bool EndChangeCheck() { throw null; }

        public struct DisabledScope : IDisposable
        {
            public DisabledScope(bool disabled) { throw null; }
            public void Dispose() { }
        }
    }

    // UnityCsReference 2022.3 Editor/Mono/EditorGUILayout.cs
    public sealed partial class EditorGUILayout
    {
        public static bool PropertyField(SerializedProperty property, bool includeChildren, params GUILayoutOption[] options) { throw null; }
        public static void HelpBox(string message, MessageType type) { }
        public static void LabelField(string label, GUIStyle style, params GUILayoutOption[] options) { }
        public static void LabelField(string label, string label2, params GUILayoutOption[] options) { }
        public static void LabelField(string label, string label2, GUIStyle style, params GUILayoutOption[] options) { }
        public static void Space() { }
        // UnityCsReference 2022.3 Editor/Mono/EditorGUILayout.cs line 895 (6000.0: line 906)
        public static int Popup(string label, int selectedIndex, string[] displayedOptions, params GUILayoutOption[] options) { throw null; }

        public class HorizontalScope : IDisposable
        {
            public HorizontalScope(params GUILayoutOption[] options) { }
            public void Dispose() { }
        }
    }

    // UnityCsReference 2022.3 Editor/Mono/GUI/EditorStyles.cs
    public sealed class EditorStyles
    {
        public static GUIStyle boldLabel { get { throw null; } }
        public static GUIStyle wordWrappedMiniLabel { get { throw null; } }
    }

    // UnityCsReference 2022.3 Editor/Mono/EditorUtility.bindings.cs (SaveFilePanelInProject: Editor/Mono/EditorUtility.cs)
    public sealed partial class EditorUtility
    {
        public static bool DisplayCancelableProgressBar(string title, string info, float progress) { throw null; }
        public static void ClearProgressBar() { }
        public static bool DisplayDialog(string title, string message, string ok, string cancel) { throw null; }
        public static string SaveFolderPanel(string title, string folder, string defaultName) { throw null; }
        public static string SaveFilePanel(string title, string directory, string defaultName, string extension) { throw null; }
        public static string SaveFilePanelInProject(string title, string defaultName, string extension, string message) { throw null; }
        public static string OpenFilePanel(string title, string directory, string extension) { throw null; }
        public static void SetDirty(Object target) { }
        public static Object InstanceIDToObject(int instanceID) { throw null; }
    }

    // UnityCsReference 2022.3 Editor/Mono/Undo/Undo.bindings.cs
    public partial class Undo
    {
        public static void RecordObject(Object objectToUndo, string name) { }
        public static void RegisterCreatedObjectUndo(Object objectToUndo, string name) { }
        public static void PerformUndo() { }
        public static void IncrementCurrentGroup() { }
    }

    // UnityCsReference 2022.3 Editor/Mono/Prefabs/PrefabUtility.bindings.cs
    public sealed partial class PrefabUtility
    {
        public static void RecordPrefabInstancePropertyModifications(Object targetObject) { }
    }

    // UnityCsReference 2022.3 Editor/Mono/MenuItem.cs
    [AttributeUsage(AttributeTargets.Method, AllowMultiple = true)]
    public sealed class MenuItem : Attribute
    {
        public MenuItem(string itemName, bool isValidateFunction, int priority) { }
    }

    // UnityCsReference 2022.3 Editor/Mono/MenuCommand.cs
    public sealed class MenuCommand
    {
        public Object context;
    }

    // UnityCsReference 2022.3 Editor/Mono/StaticEditorFlags.cs
    [Flags]
    public enum StaticEditorFlags { ContributeGI = 1, OccluderStatic = 2, BatchingStatic = 4, NavigationStatic = 8, OccludeeStatic = 16, OffMeshLinkGeneration = 32, ReflectionProbeStatic = 64 }

    // UnityCsReference 2022.3 Editor/Mono/GameObjectUtility.bindings.cs
    public sealed partial class GameObjectUtility
    {
        public static void SetParentAndAlign(GameObject child, GameObject parent) { }
        public static void EnsureUniqueNameForSibling(GameObject self) { }
        public static StaticEditorFlags GetStaticEditorFlags(GameObject go) { throw null; }
        public static void SetStaticEditorFlags(GameObject go, StaticEditorFlags flags) { }
    }

    // UnityCsReference 2022.3 Editor/Mono/Selection.bindings.cs (6000.0: Editor/Mono/Selection/Selection.bindings.cs)
    public sealed partial class Selection
    {
        public static GameObject activeGameObject { get { throw null; } set { } }
    }

    // UnityCsReference 2022.3 Editor/Mono/SceneView/SceneView.cs
    public class SceneView : ScriptableObject
    {
        public static SceneView lastActiveSceneView { get { throw null; } }
        public Vector3 pivot { get { throw null; } set { } }
        public static void RepaintAll() { }
    }

    // UnityCsReference 2022.3 Editor/Mono/DrawGizmo.cs
    [Flags]
    public enum GizmoType { Pickable = 1, NotInSelectionHierarchy = 2, NonSelected = 32, Selected = 4, Active = 8, InSelectionHierarchy = 16 }

    // UnityCsReference 2022.3 Editor/Mono/DrawGizmo.cs
    [AttributeUsage(AttributeTargets.Method)]
    public sealed class DrawGizmo : Attribute
    {
        public DrawGizmo(GizmoType gizmo) { }
    }

    // UnityCsReference 2022.3 Editor/Mono/Handles.cs
    public sealed partial class Handles
    {
        public struct DrawingScope : IDisposable
        {
            public DrawingScope(Color color, Matrix4x4 matrix) { throw null; }
            public void Dispose() { }
        }
    }

    // UnityCsReference 2022.3 Modules/AssetDatabase/Editor/ScriptBindings/AssetDatabase.bindings.cs
    public sealed partial class AssetDatabase
    {
        public static T LoadAssetAtPath<T>(string assetPath) where T : Object { throw null; }
        public static string GetAssetPath(Object assetObject) { throw null; }
        public static bool DeleteAsset(string path) { throw null; }
    }

    // UnityCsReference 2022.3 Editor/Mono/AssemblyReloadEvents.cs
    public static class AssemblyReloadEvents
    {
        public delegate void AssemblyReloadCallback();
        public static event AssemblyReloadCallback beforeAssemblyReload { add { } remove { } }
    }

    // UnityCsReference 2022.3 Editor/Mono/EditorApplication.bindings.cs
    public sealed partial class EditorApplication
    {
        public static void Exit(int returnValue) { }
        public static CallbackFunction update;
        public delegate void CallbackFunction();
    }
}

namespace UnityEditor.IMGUI.Controls
{
    // UnityCsReference 2022.3 Editor/Mono/EditorHandles/BoundsHandle/PrimitiveBoundsHandle.cs
    public abstract class PrimitiveBoundsHandle
    {
        public Vector3 center { get { throw null; } set { } }
        public void DrawHandle() { }
    }

    // UnityCsReference 2022.3 Editor/Mono/EditorHandles/BoundsHandle/BoxBoundsHandle.cs
    public class BoxBoundsHandle : PrimitiveBoundsHandle
    {
        public BoxBoundsHandle() { }
        public Vector3 size { get { throw null; } set { } }
    }
}

namespace UnityEditor.SceneManagement
{
    // UnityCsReference 2022.3 Editor/Mono/EditorSceneManager.bindings.cs
    public enum OpenSceneMode { Single = 0, Additive = 1, AdditiveWithoutLoading = 2 }

    // UnityCsReference 2022.3 Editor/Mono/EditorSceneManager.bindings.cs
    public enum NewSceneSetup { EmptyScene = 0, DefaultGameObjects = 1 }

    // UnityCsReference 2022.3 Editor/Mono/EditorSceneManager.bindings.cs
    public enum NewSceneMode { Single = 0, Additive = 1 }

    // UnityCsReference 2022.3 Editor/Mono/EditorSceneManager.bindings.cs (OpenScene, NewScene, SaveScene) and Editor/Mono/EditorSceneManager.cs
    public sealed partial class EditorSceneManager
    {
        public static UnityEngine.SceneManagement.Scene OpenScene(string scenePath, OpenSceneMode mode) { throw null; }
        public static UnityEngine.SceneManagement.Scene NewScene(NewSceneSetup setup, NewSceneMode mode) { throw null; }
        public static bool SaveScene(UnityEngine.SceneManagement.Scene scene) { throw null; }
        public static bool SaveScene(UnityEngine.SceneManagement.Scene scene, string dstScenePath) { throw null; }
        public static bool SaveCurrentModifiedScenesIfUserWantsTo() { throw null; }
    }
}

namespace UnityEditor.PackageManager
{
    // UnityCsReference 2022.3 Modules/PackageManager/Editor/Managed/Client.cs
    public static class Client
    {
        public static Requests.ListRequest List(bool offlineMode, bool includeIndirectDependencies) { throw null; }
        public static Requests.AddRequest Add(string identifier) { throw null; }
        public static Requests.RemoveRequest Remove(string packageName) { throw null; }
    }
    // UnityCsReference 2022.3 Modules/PackageManager/Editor/Managed/StatusCode.cs
    public enum StatusCode { InProgress = 0, Success = 1, Failure = 2 }
    // UnityCsReference 2022.3 Modules/PackageManager/Editor/Managed/Error.cs
    public class Error { public string message { get { throw null; } } }
    // UnityCsReference 2022.3 Modules/PackageManager/Editor/Managed/PackageInfo.cs
    public sealed class PackageInfo
    {
        public string version { get { throw null; } }
        public string name { get { throw null; } }
    }
    // UnityCsReference 2022.3 Modules/PackageManager/Editor/Managed/PackageCollection.cs
    public class PackageCollection : System.Collections.Generic.IEnumerable<PackageInfo>
    {
        System.Collections.Generic.IEnumerator<PackageInfo> System.Collections.Generic.IEnumerable<PackageInfo>.GetEnumerator() { throw null; }
        System.Collections.IEnumerator System.Collections.IEnumerable.GetEnumerator() { throw null; }
    }
}

namespace UnityEditor.PackageManager.Requests
{
    // UnityCsReference 2022.3 Modules/PackageManager/Editor/Managed/Requests/Request.cs
    public abstract partial class Request
    {
        public StatusCode Status { get { throw null; } }
        public bool IsCompleted { get { throw null; } }
        public Error Error { get { throw null; } }
    }
    public abstract class Request<T> : Request { public T Result { get { throw null; } } }
    // UnityCsReference 2022.3 Modules/PackageManager/Editor/Managed/Requests/{List,Add,Remove}Request.cs
    public sealed partial class ListRequest : Request<PackageCollection> { }
    public sealed partial class AddRequest : Request<PackageInfo> { }
    public sealed partial class RemoveRequest : Request { }
}

namespace UnityEditor
{
    // UnityCsReference 2022.3 Editor/Mono/SessionState.cs
    public class SessionState
    {
        public static bool GetBool(string key, bool defaultValue) { throw null; }
        public static void SetBool(string key, bool value) { }
    }
    // UnityCsReference 2022.3 Editor/Mono/EditorApplication.cs (attribute in Editor/Mono/InitializeOnLoad... )
    [AttributeUsage(AttributeTargets.Class)]
    public class InitializeOnLoadAttribute : Attribute { }
}
