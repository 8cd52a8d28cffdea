using System;
using System.Collections.Generic;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Sh;

namespace Lpnn.Probes.Core.Features
{
    /// <summary>The scene scale S: median DC luminance over the points that have any light. Every lighting
    /// feature is relative to it (or to a floor tied to it), which makes them invariant to exposure.</summary>
    internal static class SceneScale
    {
        public static double DcLuminance(float[] sh, int point)
        {
            int o = point * ShMath.FloatsPerProbe;
            return ColorSpaces.Luminance(sh[o], sh[o + ShMath.CoefficientsPerChannel], sh[o + 2 * ShMath.CoefficientsPerChannel]);
        }

        /// <summary>Median of the positive DC luminances (mean of the middle two for an even count); 1 when none.</summary>
        public static double Compute(float[] sh, int pointCount)
        {
            var positive = new List<double>(pointCount);
            for (int n = 0; n < pointCount; n++)
            {
                double y = DcLuminance(sh, n);
                if (y > 0) positive.Add(y);
            }
            return positive.Count == 0 ? 1.0 : Statistics.Median(positive);
        }
    }
}
