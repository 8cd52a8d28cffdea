namespace Lpnn.Probes.Core.Selection
{
    /// <summary>Measures how well a probe set reproduces the lighting: the tolerance policy needs it, and the selection
    /// code stays free of interpolation and lighting (Lpnn.Probes.Core.Quality.PlacementEvaluator implements it).</summary>
    public interface IPlacementErrorMeasure
    {
        /// <summary>Mean placement error (Documentation~/quality.md §2, the irradiance metric) of the probes at these
        /// grid point indices (sorted, distinct).</summary>
        double MeanError(int[] probeIndices);
    }
}
