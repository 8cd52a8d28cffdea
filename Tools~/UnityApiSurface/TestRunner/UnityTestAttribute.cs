// Stand-in for the Unity Test Framework member used by LPNN tests (signature only; see ../README.md).
using System;

namespace UnityEngine.TestTools
{
    // needle-mirror/com.unity.test-framework 1.4.6 UnityEngine.TestRunner/NUnitExtensions/Attributes/UnityTestAttribute.cs
    // (the real attribute derives from NUnit 3's CombiningStrategyAttribute; only its use on IEnumerator test methods matters here).
    [AttributeUsage(AttributeTargets.Method, AllowMultiple = false, Inherited = false)]
    public class UnityTestAttribute : Attribute
    {
        public UnityTestAttribute() { }
    }
}
