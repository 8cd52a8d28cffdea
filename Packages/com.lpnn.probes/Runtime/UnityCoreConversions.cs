using System.Collections.Generic;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Sh;
using UnityEngine;
using UnityEngine.Rendering;
using NumericsVector3 = System.Numerics.Vector3;

namespace Lpnn.Probes
{
    /// <summary>Conversions between Unity types and the engine-agnostic core (System.Numerics vectors, Double3,
    /// GridBox, the flat 27-float SH layout).</summary>
    internal static class UnityCoreConversions
    {
        public static NumericsVector3 ToNumerics(this Vector3 v) => new NumericsVector3(v.x, v.y, v.z);

        public static Vector3 ToUnity(this NumericsVector3 v) => new Vector3(v.X, v.Y, v.Z);

        public static Double3 ToDouble3(this Vector3 v) => new Double3(v.x, v.y, v.z);

        /// <summary>A local box through a local-to-world matrix: the centre maps as a point and the three rotated
        /// half-edges as vectors, so rotation, non-uniform scale and even shear stay exact (an affine map keeps a
        /// parallelepiped a parallelepiped).</summary>
        public static GridBox ToWorldGridBox(LpnnBox box, Matrix4x4 localToWorld)
        {
            var rotation = box.LocalRotation;
            var half = box.size * 0.5f;
            // Matrix4x4.MultiplyPoint3x4 / MultiplyVector: UnityCsReference Runtime/Export/Math/Matrix4x4.cs
            var center = localToWorld.MultiplyPoint3x4(box.center);
            var u = localToWorld.MultiplyVector(rotation * new Vector3(half.x, 0, 0));
            var v = localToWorld.MultiplyVector(rotation * new Vector3(0, half.y, 0));
            var w = localToWorld.MultiplyVector(rotation * new Vector3(0, 0, half.z));
            return new GridBox(center.ToDouble3(), u.ToDouble3(), v.ToDouble3(), w.ToDouble3());
        }

        /// <summary>World positions into the local space of <paramref name="space"/> (LightProbeGroup.probePositions is
        /// local to the group's transform: UnityCsReference Editor/Mono/Inspector/LightProbeGroupInspector.cs).</summary>
        public static Vector3[] WorldToLocal(Transform space, IReadOnlyList<NumericsVector3> world)
        {
            var worldToLocal = space.worldToLocalMatrix;
            var local = new Vector3[world.Count];
            for (int p = 0; p < local.Length; p++) local[p] = worldToLocal.MultiplyPoint3x4(world[p].ToUnity());
            return local;
        }

        /// <summary>Local positions of <paramref name="space"/> to world positions for the core.</summary>
        public static NumericsVector3[] LocalToWorld(Transform space, IReadOnlyList<Vector3> local)
        {
            var localToWorld = space.localToWorldMatrix;
            var world = new NumericsVector3[local.Count];
            for (int p = 0; p < world.Length; p++) world[p] = localToWorld.MultiplyPoint3x4(local[p]).ToNumerics();
            return world;
        }

        /// <summary>Copies Unity SH into the flat layout (index rgb*9 + coefficient, Documentation~/sh.md), which is
        /// exactly SphericalHarmonicsL2's indexer [rgb, coefficient] (Runtime/Export/Math/SphericalHarmonicsL2.bindings.cs).</summary>
        public static void CopySh(SphericalHarmonicsL2 sh, float[] destination, int offset)
        {
            for (int rgb = 0; rgb < 3; rgb++)
                for (int c = 0; c < ShMath.CoefficientsPerChannel; c++)
                    destination[offset + rgb * ShMath.CoefficientsPerChannel + c] = sh[rgb, c];
        }
    }
}
