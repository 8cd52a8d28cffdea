using System.Collections.Generic;
using UnityEditor;
using UnityEngine;

namespace Lpnn.Probes.Editor
{
    /// <summary>Finds geometry the rays would miss: renderers that take part in baked lighting (static, Contribute GI)
    /// but have no collider, so the occlusion features would see straight through them.</summary>
    internal static class ColliderAudit
    {
        public static List<MeshFilter> StaticMeshesWithoutColliders()
        {
            var missing = new List<MeshFilter>();
            foreach (var renderer in SceneObjects.FindAll<MeshRenderer>())
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
