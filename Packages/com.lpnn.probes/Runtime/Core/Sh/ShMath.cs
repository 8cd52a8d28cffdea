using System;
using System.Numerics;

namespace Lpnn.Probes.Core.Sh
{
    /// <summary>Unity <c>SphericalHarmonicsL2</c> math on flat float arrays (27 floats per probe,
    /// index <c>rgb*9 + i</c>), so millions of probes need no per-probe objects. Documentation~/sh.md.</summary>
    internal static class ShMath
    {
        public const int CoefficientsPerChannel = 9;
        public const int FloatsPerProbe = 27;

        /// <summary>Index of coefficient <paramref name="coefficient"/> of channel <paramref name="rgb"/>.</summary>
        public static int Index(int rgb, int coefficient)
        {
            if ((uint)rgb > 2) throw new ArgumentOutOfRangeException(nameof(rgb), rgb, "channel must be 0 (r), 1 (g) or 2 (b)");
            if ((uint)coefficient > 8) throw new ArgumentOutOfRangeException(nameof(coefficient), coefficient, "coefficient must be 0..8");
            return rgb * CoefficientsPerChannel + coefficient;
        }

        /// <summary>Shading value of one probe in a unit direction, in double, summed in coefficient order.</summary>
        public static void Evaluate(float[] sh, int offset, double x, double y, double z,
            out double r, out double g, out double b)
        {
            double p1 = y, p2 = z, p3 = x, p4 = x * y, p5 = y * z, p6 = 3.0 * z * z - 1.0, p7 = x * z, p8 = x * x - y * y;
            r = EvaluateChannel(sh, offset, p1, p2, p3, p4, p5, p6, p7, p8);
            g = EvaluateChannel(sh, offset + CoefficientsPerChannel, p1, p2, p3, p4, p5, p6, p7, p8);
            b = EvaluateChannel(sh, offset + 2 * CoefficientsPerChannel, p1, p2, p3, p4, p5, p6, p7, p8);
        }

        private static double EvaluateChannel(float[] s, int o, double p1, double p2, double p3, double p4,
            double p5, double p6, double p7, double p8)
        {
            double sum = s[o];
            sum += s[o + 1] * p1;
            sum += s[o + 2] * p2;
            sum += s[o + 3] * p3;
            sum += s[o + 4] * p4;
            sum += s[o + 5] * p5;
            sum += s[o + 6] * p6;
            sum += s[o + 7] * p7;
            sum += s[o + 8] * p8;
            return sum;
        }

        public static Vector3 Evaluate(float[] sh, int offset, Vector3 direction)
        {
            Evaluate(sh, offset, direction.X, direction.Y, direction.Z, out double r, out double g, out double b);
            return new Vector3((float)r, (float)g, (float)b);
        }

        /// <summary>Unity <c>AddAmbientLight</c>: adds the colour to the constant term.</summary>
        public static void AddAmbient(float[] sh, int offset, Vector3 rgb)
        {
            sh[offset] += rgb.X;
            sh[offset + CoefficientsPerChannel] += rgb.Y;
            sh[offset + 2 * CoefficientsPerChannel] += rgb.Z;
        }

        /// <summary>Unity <c>AddDirectionalLight</c>; <paramref name="direction"/> points toward the light.
        /// <c>k = 2·intensity·colour</c> is formed in float32 as Unity's managed code does.</summary>
        public static void AddDirectional(float[] sh, int offset, Vector3 direction, Vector3 rgb, float intensity)
        {
            double length = Math.Sqrt((double)direction.X * direction.X + (double)direction.Y * direction.Y + (double)direction.Z * direction.Z);
            if (!(length > 0) || double.IsInfinity(length))
                throw new ArgumentException("light direction " + direction + " has no length; pass a unit vector toward the light", nameof(direction));
            double x = direction.X / length, y = direction.Y / length, z = direction.Z / length;
            Vector3 k = rgb * (2.0f * intensity);
            var factors = new[]
            {
                4.0 / 17.0, 8.0 / 17.0 * y, 8.0 / 17.0 * z, 8.0 / 17.0 * x, 15.0 / 17.0 * x * y,
                15.0 / 17.0 * y * z, 5.0 / 68.0 * (3.0 * z * z - 1.0), 15.0 / 17.0 * x * z, 15.0 / 68.0 * (x * x - y * y),
            };
            AddScaled(sh, offset, factors, k);
        }

        /// <summary>Least-squares L2 fit of "ambient a + directed d·max(0, n·l)" per channel (Quake III light
        /// grid cells), in Unity's stored convention. <paramref name="direction"/> is a unit vector toward the light.</summary>
        public static void AmbientPlusDirected(Vector3 ambient, Vector3 directed, Vector3 direction, float[] sh, int offset)
        {
            double x = direction.X, y = direction.Y, z = direction.Z;
            var factors = new[]
            {
                0.25, 0.5 * y, 0.5 * z, 0.5 * x, 15.0 / 16.0 * x * y, 15.0 / 16.0 * y * z,
                5.0 / 64.0 * (3.0 * z * z - 1.0), 15.0 / 16.0 * x * z, 15.0 / 64.0 * (x * x - y * y),
            };
            Array.Clear(sh, offset, FloatsPerProbe);
            AddScaled(sh, offset, factors, directed);
            AddAmbient(sh, offset, ambient);
        }

        private static void AddScaled(float[] sh, int offset, double[] factors, Vector3 k)
        {
            for (int i = 0; i < CoefficientsPerChannel; i++)
            {
                sh[offset + i] = (float)(sh[offset + i] + k.X * factors[i]);
                sh[offset + CoefficientsPerChannel + i] = (float)(sh[offset + CoefficientsPerChannel + i] + k.Y * factors[i]);
                sh[offset + 2 * CoefficientsPerChannel + i] = (float)(sh[offset + 2 * CoefficientsPerChannel + i] + k.Z * factors[i]);
            }
        }

        /// <summary>Weighted blend of probes (probe interpolation): result = Σ w_k·sh[probe_k], in double.</summary>
        public static void Blend(float[] sh, int[] probes, double[] weights, int count, double[] result)
        {
            if (result.Length < FloatsPerProbe) throw new ArgumentException("result needs 27 values", nameof(result));
            Array.Clear(result, 0, FloatsPerProbe);
            for (int k = 0; k < count; k++)
            {
                int o = probes[k] * FloatsPerProbe;
                double w = weights[k];
                for (int c = 0; c < FloatsPerProbe; c++) result[c] += w * sh[o + c];
            }
        }

        /// <summary>True when all 27 coefficients of the probe at <paramref name="offset"/> are finite.</summary>
        public static bool IsFinite(float[] sh, int offset)
        {
            for (int c = 0; c < FloatsPerProbe; c++)
            {
                float v = sh[offset + c];
                if (float.IsNaN(v) || float.IsInfinity(v)) return false;
            }
            return true;
        }
    }
}
