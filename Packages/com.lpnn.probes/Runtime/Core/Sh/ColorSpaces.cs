using System.Numerics;

namespace Lpnn.Probes.Core.Sh
{
    /// <summary>Rec. 709 luminance and the YCoCg transform LumiProbes compares colours in.</summary>
    internal static class ColorSpaces
    {
        public const double LuminanceR = 0.2126;
        public const double LuminanceG = 0.7152;
        public const double LuminanceB = 0.0722;

        public static double Luminance(double r, double g, double b) => LuminanceR * r + LuminanceG * g + LuminanceB * b;

        public static float Luminance(Vector3 rgb) => (float)Luminance(rgb.X, rgb.Y, rgb.Z);

        /// <summary>(Y, Co, Cg) = (R/4 + G/2 + B/4, R/2 − B/2, −R/4 + G/2 − B/4).</summary>
        public static Vector3 RgbToYCoCg(Vector3 rgb)
        {
            RgbToYCoCg(rgb.X, rgb.Y, rgb.Z, out double y, out double co, out double cg);
            return new Vector3((float)y, (float)co, (float)cg);
        }

        /// <summary>The same transform in double (the placement metric compares lighting without float32 rounding).</summary>
        public static void RgbToYCoCg(double r, double g, double b, out double y, out double co, out double cg)
        {
            y = r / 4 + g / 2 + b / 4;
            co = r / 2 - b / 2;
            cg = -r / 4 + g / 2 - b / 4;
        }

        public static Vector3 YCoCgToRgb(Vector3 ycocg)
        {
            double y = ycocg.X, co = ycocg.Y, cg = ycocg.Z;
            return new Vector3((float)(y + co - cg), (float)(y + cg), (float)(y - co - cg));
        }
    }
}
