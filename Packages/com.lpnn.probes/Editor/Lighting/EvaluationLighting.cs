using Lpnn.Probes.Core;

namespace Lpnn.Probes.Editor
{
    /// <summary>Picks the lighting implementation for a volume's Lighting source on this Unity version.</summary>
    public static class EvaluationLighting
    {
        /// <summary>True when the volume's source would regenerate the scene's lighting data (Unity 2022.3's only way
        /// to bake arbitrary points), so the user must agree first.</summary>
        public static bool RewritesSceneLighting(LpnnVolume volume)
        {
#if UNITY_6000_0_OR_NEWER
            return false;
#else
            return volume.Lighting == LightingSource.BakeAtEvaluationPoints;
#endif
        }

        /// <summary>What the source will do, for the inspector.</summary>
        public static string Explain(LpnnVolume volume)
        {
            if (volume.Lighting == LightingSource.InterpolateSceneProbes)
                return "Interpolates the scene's existing baked light probes at every point. Nothing is baked or written; " +
                       "the result is only as detailed as the probes you already have.";
#if UNITY_6000_0_OR_NEWER
            return "Lights every point with Unity's GPU light baker (LightTransport) in memory, using this scene's Lighting Settings. " +
                   "Nothing is baked or written: your lightmaps and probes stay as they are.";
#else
            return "Unity 2022.3 can bake arbitrary points only inside a full bake: this runs Generate Lighting with the scene's current " +
                   "Lighting Settings (replacing the scene's lighting data with a fresh bake of the same settings) and reads the points back. " +
                   "You are asked before it starts.";
#endif
        }

        /// <param name="sceneBakeAllowed">The user agreed to regenerate the scene's lighting (only consulted where that is needed).</param>
        public static IEvaluationLighting Create(LpnnVolume volume, bool sceneBakeAllowed)
        {
            if (volume.Lighting == LightingSource.InterpolateSceneProbes) return new SceneProbeInterpolation();
#if UNITY_6000_0_OR_NEWER
            return new LightTransportProbeSampler();
#else
            if (!sceneBakeAllowed)
                throw new LpnnException("baking at the evaluation points regenerates this scene's lighting data on Unity 2022.3; confirm the " +
                                        "dialog in the inspector (batch mode: pass -lpnnBake), or set Lighting source to 'Interpolate Scene Probes'");
            return new AdditionalProbesBake(volume.GetInstanceID(), volume.gameObject.scene.path);
#endif
        }
    }
}
