using System.Collections.Generic;
using UnityEditor;
using UnityEngine;
using UnityEngine.SceneManagement;

namespace Lpnn.Probes.Editor
{
    /// <summary>Finds geometry the rays would miss: renderers that take part in baked lighting (static, Contribute GI)
    /// but have no collider, so the occlusion features would see straight through them.</summary>
    internal static class ColliderAudit
    {
        /// <param name="scene">The volume's scene: in Prefab Mode only its stage's objects share the rays' physics scene.</param>
        public static List<MeshFilter> StaticMeshesWithoutColliders(Scene scene)
        {
            var missing = new List<MeshFilter>();
            foreach (var renderer in SceneObjects.SharingPhysicsWith<MeshRenderer>(scene))
            {
                if (!renderer.enabled || !renderer.gameObject.activeInHierarchy) continue;
                // GameObjectUtility.GetStaticEditorFlags: Editor/Mono/GameObjectUtility.bindings.cs; flags: Editor/Mono/StaticEditorFlags.cs.
                if ((GameObjectUtility.GetStaticEditorFlags(renderer.gameObject) & StaticEditorFlags.ContributeGI) == 0) continue;
                if (renderer.GetComponent<Collider>() != null) continue;
                var filter = renderer.GetComponent<MeshFilter>();
                if (filter != null && filter.sharedMesh != null) missing.Add(filter);
            }
            return missing;
        }
    }
}
