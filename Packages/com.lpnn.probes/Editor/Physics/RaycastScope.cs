using System;
using System.Collections.Generic;
using UnityEngine;

namespace Lpnn.Probes.Editor
{
    /// <summary>Prepares physics for edit-mode ray casts and undoes every change on Dispose: the volume's own colliders
    /// are disabled (the rays must see the scene, not the volume), temporary MeshColliders are added to static meshes
    /// that lack one (when asked), and Physics.SyncTransforms() makes edit-mode moves visible to queries (there is no
    /// simulation step outside Play Mode; Modules/Physics/ScriptBindings/Dynamics.bindings.cs 2022.3, Physics.bindings.cs 6000.0).</summary>
    internal sealed class RaycastScope : IDisposable
    {
        private readonly List<Collider> _disabled = new List<Collider>();
        private readonly List<MeshCollider> _added = new List<MeshCollider>();

        /// <summary>Static meshes without colliders that the rays cannot see (empty when temporary colliders were added).</summary>
        public IReadOnlyList<MeshFilter> Uncovered { get; }

        public RaycastScope(LpnnVolume volume, bool addTemporaryColliders)
        {
            try
            {
                foreach (var collider in volume.GetComponentsInChildren<Collider>())
                {
                    if (!collider.enabled) continue;
                    collider.enabled = false;
                    _disabled.Add(collider);
                }
                var missing = ColliderAudit.StaticMeshesWithoutColliders(volume.gameObject.scene);
                if (addTemporaryColliders)
                {
                    foreach (var filter in missing)
                    {
                        var collider = filter.gameObject.AddComponent<MeshCollider>();
                        // Never saved, never shown: it only exists while the rays are cast.
                        collider.hideFlags = HideFlags.HideAndDontSave;
                        collider.sharedMesh = filter.sharedMesh;
                        _added.Add(collider);
                    }
                    missing.Clear();
                }
                Uncovered = missing;
                Physics.SyncTransforms();
            }
            catch
            {
                Dispose();
                throw;
            }
        }

        public void Dispose()
        {
            foreach (var collider in _added)
                if (collider != null) UnityEngine.Object.DestroyImmediate(collider);
            _added.Clear();
            foreach (var collider in _disabled)
                if (collider != null) collider.enabled = true;
            _disabled.Clear();
            Physics.SyncTransforms();
        }
    }
}
