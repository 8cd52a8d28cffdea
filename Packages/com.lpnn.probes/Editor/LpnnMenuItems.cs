using UnityEditor;
using UnityEditor.SceneManagement;
using UnityEngine;

namespace Lpnn.Probes.Editor
{
    /// <summary>GameObject > Light > LPNN Probes, right after Unity's Light Probe Group, whose priority is 21 on 2022.3 and
    /// 80009 from 6000.0 (UnityCsReference Editor/Mono/Commands/GOCreationCommands.cs of each branch). Creates the volume
    /// with its LightProbeGroup and the shipped model.</summary>
    public static class LpnnMenuItems
    {
        public const string MenuPath = "GameObject/Light/LPNN Probes";
#if UNITY_6000_0_OR_NEWER
        public const int MenuPriority = 80010;
#else
        public const int MenuPriority = 22;
#endif

        [MenuItem(MenuPath, false, MenuPriority)]
        private static void CreateFromMenu(MenuCommand command)
        {
            var volume = CreateVolume(command.context as GameObject);
            // Selection.activeGameObject: Editor/Mono/Selection.bindings.cs
            Selection.activeGameObject = volume.gameObject;
        }

        /// <summary>Creates "LPNN Probes" (the volume) with a child "LPNN Light Probes" (its LightProbeGroup), parented to
        /// <paramref name="parent"/> when given, as one Undo step.</summary>
        public static LpnnVolume CreateVolume(GameObject parent)
        {
            var root = new GameObject("LPNN Probes");
            // GameObjectUtility.SetParentAndAlign / EnsureUniqueNameForSibling: Editor/Mono/GameObjectUtility.bindings.cs
            GameObjectUtility.SetParentAndAlign(root, parent);
            if (parent == null)
            {
                if (SceneView.lastActiveSceneView != null) root.transform.position = SceneView.lastActiveSceneView.pivot;
                // In Prefab Mode a new object belongs to the open prefab, not to the main scene: Unity's own creation menus
                // call this for parentless objects (Editor/Mono/Commands/GOCreationCommands.cs Place;
                // Editor/Mono/SceneManagement/StageManager/StageUtility.cs).
                StageUtility.PlaceGameObjectInCurrentStage(root);
            }
            GameObjectUtility.EnsureUniqueNameForSibling(root);
            var volume = root.AddComponent<LpnnVolume>();

            var probes = new GameObject("LPNN Light Probes");
            GameObjectUtility.SetParentAndAlign(probes, root);
            var group = probes.AddComponent<LightProbeGroup>();
            group.probePositions = new Vector3[0];

            var model = AssetDatabase.LoadAssetAtPath<Object>(LpnnPaths.ShippedModel);
            var card = AssetDatabase.LoadAssetAtPath<TextAsset>(LpnnPaths.ShippedModelCard);
            volume.Configure(group, model, card);
            Undo.RegisterCreatedObjectUndo(root, "Create LPNN Probes");
            return volume;
        }
    }
}
