namespace Lpnn.Probes
{
    /// <summary>Where the baked lighting (SH) at every evaluation point comes from. Documentation~/index.md explains
    /// what each choice touches on each Unity version. Values are stored in scenes (Unity serializes the number), so new
    /// sources are only ever appended (pinned by Tests/Editor/Data/LpnnVolume_0.1.0.prefab).</summary>
    public enum LightingSource
    {
        /// <summary>Light each evaluation point with Unity's light baker. Unity 6: probe integration through
        /// UnityEngine.LightTransport, which writes no lighting data. Unity 2022.3: the points are added to a full
        /// bake ("Generate Lighting") as additional probes, which rewrites the scene's lighting data from its current
        /// Lighting Settings, so the editor asks first.</summary>
        BakeAtEvaluationPoints = 0,

        /// <summary>Interpolate the scene's already baked light probes at each point (no bake, nothing written);
        /// only as detailed as the probes that exist.</summary>
        InterpolateSceneProbes = 1,
    }
}
