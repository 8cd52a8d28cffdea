namespace Lpnn.Probes.Core.Quality
{
    /// <summary>What <see cref="BatchedRefinement"/> kept: evaluation point indices (sorted ascending), their mean
    /// irradiance error (leak-weighted when the refinement weighed leaks, Documentation~/leaks.md "A leak-aware default"),
    /// the rounds run and why it stopped.</summary>
    public sealed class BatchedRefinementResult
    {
        public const string StoppedAtCount = "count";
        public const string StoppedAtTolerance = "tolerance";
        public const string StoppedAtMinimum = "minimum count";
        public const string StoppedFlat = "the rest would lie in one plane";
        public const string SeedAboveTolerance = "the seed exceeds the tolerance";

        public int[] Indices { get; }
        public double MeanError { get; }
        public int Rounds { get; }
        /// <summary>One of the constants above; <see cref="SeedAboveTolerance"/> means <see cref="Indices"/> is the seed, unrefined.</summary>
        public string StopReason { get; }

        public BatchedRefinementResult(int[] indices, double meanError, int rounds, string stopReason)
        {
            Indices = indices;
            MeanError = meanError;
            Rounds = rounds;
            StopReason = stopReason;
        }
    }
}
