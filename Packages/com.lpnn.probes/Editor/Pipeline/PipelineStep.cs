namespace Lpnn.Probes.Editor
{
    /// <summary>The steps of a volume's pipeline, in the order <see cref="LpnnPipeline.Run"/> runs them.</summary>
    public enum PipelineStep
    {
        Grid = 0,
        Lighting = 1,
        Features = 2,
        Scoring = 3,
        Placement = 4,
    }
}
