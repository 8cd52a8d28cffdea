using System.Threading;
using Lpnn.Probes.Core;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Sh;
using UnityEngine;
using UnityEngine.Rendering;
using NumericsVector3 = System.Numerics.Vector3;

namespace Lpnn.Probes.Editor
{
    /// <summary>Lighting from the scene's existing baked light probes, interpolated the way renderers see them
    /// (LightProbes.CalculateInterpolatedLightAndOcclusionProbes: UnityCsReference Runtime/Export/Graphics/Graphics.bindings.cs).
    /// Bakes nothing and writes nothing; only as detailed as the probes that already exist.</summary>
    internal sealed class SceneProbeInterpolation : IEvaluationLighting, ILightSampler
    {
        public string Description => "interpolated from the scene's baked light probes";

        public float[] Sample(EvaluationGrid grid, ProgressCallback progress, CancellationToken cancel)
        {
            var probes = LightmapSettings.lightProbes;
            if (probes == null || probes.count == 0)
                throw new LpnnException("the scene has no baked light probes to interpolate; bake the lighting with a LightProbeGroup " +
                                        "covering the volume, or set Lighting source to 'Bake At Evaluation Points'");
            return FeatureExtractor.SampleLighting(grid, this, progress, cancel);
        }

        public void Sample(NumericsVector3[] positions, float[] sh)
        {
            var unityPositions = new Vector3[positions.Length];
            for (int p = 0; p < positions.Length; p++) unityPositions[p] = positions[p].ToUnity();
            var probes = new SphericalHarmonicsL2[positions.Length];
            LightProbes.CalculateInterpolatedLightAndOcclusionProbes(unityPositions, probes, null);
            for (int p = 0; p < probes.Length; p++) UnityCoreConversions.CopySh(probes[p], sh, p * ShMath.FloatsPerProbe);
        }

        public void Dispose() { }
    }
}
