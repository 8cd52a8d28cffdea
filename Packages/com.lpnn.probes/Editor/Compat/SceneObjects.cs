using System.Collections.Generic;
using UnityEditor.SceneManagement;
using UnityEngine;
using UnityEngine.SceneManagement;

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

        /// <summary>The active objects of a type that share physics with <paramref name="scene"/>: those of a preview scene
        /// (Prefab Mode's stage: UnityCsReference 6000.0 Editor/Mono/SceneManagement/StageManager/PrefabStage/PrefabStage.cs,
        /// EditorSceneManager.NewPreviewScene), which FindObjectsByType does not search, read from its roots
        /// (Runtime/Export/SceneManager/Scene.cs GetRootGameObjects; EditorSceneManager.bindings.cs IsPreviewScene); else
        /// every loaded scene's, which share the default physics scene.</summary>
        public static T[] SharingPhysicsWith<T>(Scene scene) where T : Component
        {
            if (!scene.IsValid() || !EditorSceneManager.IsPreviewScene(scene)) return FindAll<T>();
            var found = new List<T>();
            foreach (var root in scene.GetRootGameObjects()) found.AddRange(root.transform.GetComponentsInChildren<T>());
            return found.ToArray();
        }
    }
}
