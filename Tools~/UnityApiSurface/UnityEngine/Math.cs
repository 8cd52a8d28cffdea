// Stand-ins for UnityEngine math types used by LPNN (signatures only; see ../README.md).
namespace UnityEngine
{
    // UnityCsReference 2022.3 Runtime/Export/Math/Vector3.cs
    public struct Vector3
    {
        public float x, y, z;
        public Vector3(float x, float y, float z) { this.x = x; this.y = y; this.z = z; }
        public static Vector3 zero { get { throw null; } }
        public static Vector3 one { get { throw null; } }
        public static float Distance(Vector3 a, Vector3 b) { throw null; }
        public static Vector3 operator +(Vector3 a, Vector3 b) { throw null; }
        public static Vector3 operator -(Vector3 a, Vector3 b) { throw null; }
        public static Vector3 operator *(Vector3 a, float d) { throw null; }
        public static Vector3 operator *(float d, Vector3 a) { throw null; }
    }

    // UnityCsReference 2022.3 Runtime/Export/Math/Vector4.cs
    public struct Vector4
    {
        public float x, y, z, w;
    }

    // UnityCsReference 2022.3 Runtime/Export/Math/Quaternion.cs
    public struct Quaternion
    {
        public static Quaternion Euler(Vector3 euler) { throw null; }
        public static Quaternion Euler(float x, float y, float z) { throw null; }
        public static Vector3 operator *(Quaternion rotation, Vector3 point) { throw null; }
    }

    // UnityCsReference 2022.3 Runtime/Export/Math/Matrix4x4.cs
    public struct Matrix4x4
    {
        public Vector3 MultiplyPoint3x4(Vector3 point) { throw null; }
        public Vector3 MultiplyVector(Vector3 vector) { throw null; }
        public static Matrix4x4 TRS(Vector3 pos, Quaternion q, Vector3 s) { throw null; }
        public static Matrix4x4 operator *(Matrix4x4 lhs, Matrix4x4 rhs) { throw null; }
    }

    // UnityCsReference 2022.3 Runtime/Export/Math/Color.cs
    public struct Color
    {
        public float r, g, b, a;
        public Color(float r, float g, float b, float a) { this.r = r; this.g = g; this.b = b; this.a = a; }
        public Color(float r, float g, float b) { this.r = r; this.g = g; this.b = b; a = 1f; }
        public static Color white { get { throw null; } }
        public static Color Lerp(Color a, Color b, float t) { throw null; }
    }

    // UnityCsReference 2022.3 Runtime/Export/Math/Mathf.cs
    public struct Mathf
    {
        public static float Max(float a, float b) { throw null; }
        public static int Max(int a, int b) { throw null; }
        public static float Abs(float f) { throw null; }
        public static float Clamp01(float value) { throw null; }
        public static int CeilToInt(float f) { throw null; }
    }
}

namespace UnityEngine.Rendering
{
    // UnityCsReference 2022.3 Runtime/Export/Math/SphericalHarmonicsL2.bindings.cs
    public struct SphericalHarmonicsL2
    {
        public float this[int rgb, int coefficient] { get { throw null; } set { } }
    }
}
