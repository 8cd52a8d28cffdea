using System.Numerics;

namespace Lpnn.Probes.Core.Features
{
    /// <summary>Baked lighting at arbitrary positions, in Unity's SphericalHarmonicsL2 layout.
    /// Unity: baked probes at the evaluation points; headless: the Quake III light grid; tests: analytic fields.</summary>
    public interface ILightSampler
    {
        /// <summary>Writes 27 floats (index rgb*9 + coefficient) for each position into
        /// <paramref name="sh"/>[27·n … 27·n + 26]. <paramref name="sh"/> holds at least 27 × positions.Length floats.</summary>
        void Sample(Vector3[] positions, float[] sh);
    }
}
