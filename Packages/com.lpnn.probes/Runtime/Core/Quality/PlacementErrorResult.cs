namespace Lpnn.Probes.Core.Quality
{
    /// <summary>How well a probe set reproduces the reference lighting (Documentation~/quality.md §2).</summary>
    public sealed class PlacementErrorResult
    {
        public int ProbeCount { get; }
        /// <summary>Evaluation points outside the probes' hull (interpolated from their nearest hull point).</summary>
        public int OutsidePoints { get; }
        /// <summary>Relative irradiance error: the primary metric (tolerance policy, references, labels).</summary>
        public ErrorSummary Irradiance { get; }
        /// <summary>YCoCg SMAPE (LumiProbes' metric, without its bugs).</summary>
        public ErrorSummary Smape { get; }
        /// <summary>e_irr per evaluation point (0 at the probes).</summary>
        public double[] PointIrradiance { get; }
        /// <summary>e_smape per evaluation point (0 at the probes).</summary>
        public double[] PointSmape { get; }

        public PlacementErrorResult(int probeCount, int outsidePoints, double[] pointIrradiance, double[] pointSmape)
        {
            ProbeCount = probeCount;
            OutsidePoints = outsidePoints;
            PointIrradiance = pointIrradiance;
            PointSmape = pointSmape;
            Irradiance = ErrorSummary.Of(pointIrradiance);
            Smape = ErrorSummary.Of(pointSmape);
        }
    }
}
