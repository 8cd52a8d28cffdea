using System;
using Lpnn.Probes.Core.Sh;

namespace Lpnn.Probes.Core.Quality
{
    /// <summary>The two per-point errors of Documentation~/quality.md §2, on the 42 values (D14 × RGB) of an
    /// interpolated and a reference lighting. Both are in [0, 1] and invariant to exposure: every term, including the
    /// floor ε·S, scales with the lighting.</summary>
    internal static class PointErrorMetrics
    {
        /// <summary>ε: points darker than 1 % of the typical brightness S are compared against that floor.</summary>
        public const double Epsilon = 0.01;

        /// <summary>e_irr = Σ|E_int − E_ref| / (Σ(|E_int| + |E_ref|) + 42·ε·S): bounded, so a black point receiving leaked
        /// light counts 1 instead of exploding.</summary>
        public static double Irradiance(double[] interpolated, double[] reference, int referenceOffset, double sceneScale)
        {
            const int values = ReferenceLighting.LightValues;
            double difference = 0, magnitude = 0;
            for (int i = 0; i < values; i++)
            {
                double x = interpolated[i], y = reference[referenceOffset + i];
                difference += Math.Abs(x - y);
                magnitude += Math.Abs(x) + Math.Abs(y);
            }
            // The floor is > 0 (S > 0), so the ratio is always defined; 0/floor = 0 for an exact match.
            return difference / (magnitude + values * Epsilon * sceneScale);
        }

        /// <summary>YCoCg SMAPE: the mean over the 42 YCoCg values of |x − y| / (|x| + |y| + ε·S) (LumiProbes' metric
        /// without its bugs).</summary>
        public static double Smape(double[] interpolated, double[] reference, int referenceOffset, double sceneScale)
        {
            const int values = ReferenceLighting.LightValues;
            double floor = Epsilon * sceneScale, sum = 0;
            for (int i = 0; i < values; i += 3)
            {
                ColorSpaces.RgbToYCoCg(interpolated[i], interpolated[i + 1], interpolated[i + 2], out double xy, out double xco, out double xcg);
                int o = referenceOffset + i;
                ColorSpaces.RgbToYCoCg(reference[o], reference[o + 1], reference[o + 2], out double yy, out double yco, out double ycg);
                sum += Term(xy, yy, floor) + Term(xco, yco, floor) + Term(xcg, ycg, floor);
            }
            return sum / values;
        }

        private static double Term(double x, double y, double floor) => Math.Abs(x - y) / (Math.Abs(x) + Math.Abs(y) + floor);
    }
}
