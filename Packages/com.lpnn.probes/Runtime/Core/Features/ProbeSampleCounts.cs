using System;

namespace Lpnn.Probes.Core.Features
{
    /// <summary>The ray counts Unity's own probe baker gives each probe, so evaluation points are lit like the probes a bake
    /// would produce. Unity-Technologies/Graphics, SRP Core Editor/Lighting/ProbeVolume/ProbeGIBaking.LightTransport.cs
    /// (BakeJob.Create): direct = directSampleCount × m, indirect = max(indirectSampleCount, environmentSampleCount) × m and
    /// validity = the indirect count, where m = (int)LightingSettings.lightProbeSampleCountMultiplier ("probes sample a larger
    /// area than a lightmap texel", default 4). Counts below one (an empty or hostile Lighting Settings asset) become one:
    /// the integrators need at least one ray.</summary>
    internal struct ProbeSampleCounts
    {
        public int Direct;
        public int Indirect;
        public int Validity;

        public static ProbeSampleCounts FromLightingSettings(int directSampleCount, int indirectSampleCount, int environmentSampleCount,
                                                            float lightProbeSampleCountMultiplier)
        {
            // Unity truncates the multiplier to an int; NaN or a negative value is treated as the smallest useful one.
            long multiplier = float.IsNaN(lightProbeSampleCountMultiplier) || lightProbeSampleCountMultiplier < 1f
                ? 1L
                : (long)Math.Min(lightProbeSampleCountMultiplier, int.MaxValue);
            long indirect = Math.Max(indirectSampleCount, environmentSampleCount);
            return new ProbeSampleCounts
            {
                Direct = Clamp(directSampleCount * multiplier),
                Indirect = Clamp(indirect * multiplier),
                Validity = Clamp(indirect * multiplier),
            };
        }

        private static int Clamp(long count) => (int)Math.Max(1L, Math.Min(count, int.MaxValue));
    }
}
