// Stand-ins for UnityEngine lighting, rendering and gizmo members used by LPNN (signatures only; see ../README.md).
using UnityEngine.Rendering;

namespace UnityEngine
{
    // UnityCsReference 2022.3 Runtime/Export/Graphics/LightProbeGroup.bindings.cs (probe positions are local to the group)
    public sealed class LightProbeGroup : Behaviour
    {
        public Vector3[] probePositions { get { throw null; } set { } }
    }

    // UnityCsReference 2022.3 Runtime/Export/Graphics/Graphics.bindings.cs
    public sealed class LightProbes : Object
    {
        public int count { get { throw null; } }
        public static void CalculateInterpolatedLightAndOcclusionProbes(Vector3[] positions, SphericalHarmonicsL2[] lightProbes, Vector4[] occlusionProbes) { }
    }

    // UnityCsReference 2022.3 Runtime/Export/Graphics/Graphics.bindings.cs
    public sealed class LightmapSettings : Object
    {
        public static LightProbes lightProbes { get { throw null; } set { } }
    }

    // UnityCsReference 2022.3 Runtime/Export/Graphics/GraphicsEnums.cs
    public enum LightType { Spot = 0, Directional = 1, Point = 2, Area = 3, Rectangle = 3, Disc = 4 }

    // UnityCsReference 2022.3 Runtime/Export/Graphics/GraphicsEnums.cs
    public enum LightmapBakeType { Realtime = 4, Baked = 2, Mixed = 1 }

    // UnityCsReference 2022.3 Runtime/Export/Graphics/Light.bindings.cs
    public sealed class Light : Behaviour
    {
        public LightType type { get { throw null; } set { } }
        public Color color { get { throw null; } set { } }
        public float intensity { get { throw null; } set { } }
        public float range { get { throw null; } set { } }
        public LightmapBakeType lightmapBakeType { get { throw null; } set { } }
    }

    // UnityCsReference 2022.3 Runtime/Export/GI/LightingSettings.bindings.cs (6000.0: same members)
    public sealed class LightingSettings : Object
    {
        public bool bakedGI { get { throw null; } set { } }
        public float indirectScale { get { throw null; } set { } }
        public int directSampleCount { get { throw null; } set { } }
        public int indirectSampleCount { get { throw null; } set { } }
        public int maxBounces { get { throw null; } set { } }
    }

    // UnityCsReference 2022.3 Runtime/Export/Graphics/GraphicsRenderers.bindings.cs
    public class Renderer : Component
    {
        public bool enabled { get { throw null; } set { } }
        public Material sharedMaterial { get { throw null; } set { } }
    }

    // UnityCsReference 2022.3 Runtime/Export/Graphics/GraphicsRenderers.bindings.cs
    public class MeshRenderer : Renderer { }

    // UnityCsReference 2022.3 Runtime/Export/Graphics/GraphicsComponents.bindings.cs
    public sealed class MeshFilter : Component
    {
        public Mesh sharedMesh { get { throw null; } set { } }
    }

    // UnityCsReference 2022.3 Runtime/Export/Graphics/Mesh.bindings.cs
    public sealed class Mesh : Object { }

    // UnityCsReference 2022.3 Runtime/Export/Shaders/Material.bindings.cs
    public class Material : Object
    {
        public Material(Material source) { }
        public Color color { get { throw null; } set { } }
        public void SetColor(string name, Color value) { }
    }

    // UnityCsReference 2022.3 Runtime/Export/Gizmos/Gizmos.bindings.cs
    public sealed class Gizmos
    {
        public static Color color { get { throw null; } set { } }
        public static Matrix4x4 matrix { get { throw null; } set { } }
        public static void DrawWireCube(Vector3 center, Vector3 size) { }
        public static void DrawCube(Vector3 center, Vector3 size) { }
        public static void DrawWireSphere(Vector3 center, float radius) { }
    }

    // UnityCsReference 2022.3 Modules/IMGUI/GUIStyle.bindings.cs
    public sealed class GUIStyle { }

    // UnityCsReference 2022.3 Modules/IMGUI/GUILayoutOption.cs
    public sealed class GUILayoutOption { }

    // UnityCsReference 2022.3 Modules/IMGUI/GUILayout.cs
    public class GUILayout
    {
        public static bool Button(string text, params GUILayoutOption[] options) { throw null; }
        public static GUILayoutOption Width(float width) { throw null; }
    }

    // UnityCsReference 2022.3 Modules/IMGUI/GUIUtility.cs
    public class GUIUtility
    {
        public static void ExitGUI() { }
    }
}
