using System.Collections.Generic;
using UnityEditor;
using UnityEngine;

namespace Lpnn.Probes.Editor
{
    /// <summary>Finds geometry the rays would miss: renderers that take part in baked lighting (static, Contribute GI)
    /// but have no collider, so the occlusion features would see straight through them.</summary>
    public static class ColliderAudit
    {
        public static List<MeshFilter> StaticMeshesWithoutColliders()
        {
            var missing = new List<MeshFilter>();
            // FindObjectsByType: UnityCsReference Runtime/Export/Scripting/UnityEngineObject.bindings.cs (2021.3.18+, 2022.2+).
            foreach (var renderer in Object.FindObjectsByType<MeshRenderer>(FindObjectsSortMode.None))
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
