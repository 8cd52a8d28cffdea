// Stand-ins for the baking members used by LPNN (signatures only; see ../README.md).
using Unity.Collections;
using UnityEngine;
using UnityEngine.Rendering;

namespace UnityEditor
{
    // UnityCsReference 2022.3 Editor/Mono/GI/Lightmapping.bindings.cs (6000.0: same members)
    public static partial class Lightmapping
    {
        public static bool isRunning { get { throw null; } }
        public static bool Bake() { throw null; }
        public static bool TryGetLightingSettings(out LightingSettings settings) { throw null; }

        // Same file: 2022.3 line 450, 6000.0 line 416 (plain UnityEditor namespace, public, not [Obsolete] in either).
        // "Calculates a Delaunay Tetrahedralization of the 'positions' point set - the same way the lightmapper"; every 4
        // indices form one tetrahedron, near-duplicate positions are dropped, so outPositions may be shorter.
        public static void Tetrahedralize(Vector3[] positions, out int[] outIndices, out Vector3[] outPositions) { throw null; }
    }
}

#if !UNITY_6000_0_OR_NEWER
namespace UnityEditor.Experimental
{
    // UnityCsReference 2022.3 Editor/Mono/GI/Lightmapping.bindings.cs, namespace UnityEditor.Experimental.
    // Not declared for 6000.0, where these members are [Obsolete("Please use UnityEngine.LightTransport.IProbeIntegrator instead.")]
    // and LPNN uses LightTransport instead. The two-array GetAdditionalBakedProbes overload is [Obsolete] in 2022.3 too.
    public sealed partial class Lightmapping
    {
        public static void SetAdditionalBakedProbes(int id, Vector3[] positions) { }
        public static bool GetAdditionalBakedProbes(int id, NativeArray<SphericalHarmonicsL2> outBakedProbeSH, NativeArray<float> outBakedProbeValidity,
            NativeArray<float> outBakedProbeOctahedralDepth) { throw null; }
    }
}
#endif
