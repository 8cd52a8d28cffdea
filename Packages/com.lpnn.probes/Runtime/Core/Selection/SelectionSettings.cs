using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Core.Selection
{
    /// <summary>Values are stored in scenes (Unity serializes the number), so new policies are only ever appended.</summary>
    public enum SelectionPolicy
    {
        /// <summary>The thesis' threshold: p = 0.9 keeps the top 10 % (rounded, halves up).</summary>
        Percentile = 0,
        /// <summary>Top-K: the K highest-ranked points.</summary>
        Budget = 1,
        /// <summary>Points whose remapped score is at least t.</summary>
        Threshold = 2,
        /// <summary>The first K points of the spread ranking (the ranking behind the default Tolerance policy).</summary>
        Spread = 3,
        /// <summary>The smallest prefix of the spread ranking whose mean placement error is at most τ (the default policy).</summary>
        Tolerance = 4,
    }

    /// <summary>How to turn scores into probes (Documentation~/selection.md).</summary>
    public struct SelectionSettings
    {
        /// <summary>The tolerance an artist gets by default, in the Unity volume as in `lpnn place/bench/demo` and the recipe's
        /// evaluation (Python: lpnn/quality/placement/policy_rules.py DEFAULT_TOLERANCE): a mean irradiance error of 0.05 (~10 % relative
        /// irradiance error). At 0.02 the noisy Quake III light grids of our benchmarks need about 2/3 of all points, which is
        /// no reduction; the figures in Documentation~/benchmarks.md are measured at this value, so they describe the default.</summary>
        public const double DefaultTolerance = 0.05;

        /// <summary>The default policy: the fewest probes that reproduce the sampled lighting within DefaultTolerance ("as few
        /// probes as the lighting needs", README). A fixed budget would not follow the volume: too many probes in a corridor,
        /// too few in a level.</summary>
        public const SelectionPolicy DefaultPolicy = SelectionPolicy.Tolerance;

        public SelectionPolicy Policy;

        /// <summary>p ∈ [0, 1] for Percentile, K ≥ 1 (whole number) for Budget and Spread, t ∈ [0, 1] for Threshold,
        /// τ &gt; 0 for Tolerance.</summary>
        public double Value;

        /// <summary>Also keep the grid points at the 8 corners of every box, so the probe hull encloses the volume.</summary>
        public bool KeepBoundsCorners;

        public static SelectionSettings Percentile(double p, bool keepCorners = false) =>
            new SelectionSettings { Policy = SelectionPolicy.Percentile, Value = p, KeepBoundsCorners = keepCorners };

        public static SelectionSettings Budget(int count, bool keepCorners = false) =>
            new SelectionSettings { Policy = SelectionPolicy.Budget, Value = count, KeepBoundsCorners = keepCorners };

        public static SelectionSettings Threshold(double t, bool keepCorners = false) =>
            new SelectionSettings { Policy = SelectionPolicy.Threshold, Value = t, KeepBoundsCorners = keepCorners };

        public static SelectionSettings Spread(int count, bool keepCorners = false) =>
            new SelectionSettings { Policy = SelectionPolicy.Spread, Value = count, KeepBoundsCorners = keepCorners };

        public static SelectionSettings Tolerance(double tau, bool keepCorners = false) =>
            new SelectionSettings { Policy = SelectionPolicy.Tolerance, Value = tau, KeepBoundsCorners = keepCorners };

        public void Validate()
        {
            string value = InvariantFormat.Number(Value);
            switch (Policy)
            {
                case SelectionPolicy.Percentile:
                    if (!(Value >= 0 && Value <= 1))
                        throw new SelectionException("percentile " + value + " must be between 0 and 1 (0.9 keeps the top 10 %)");
                    break;
                case SelectionPolicy.Budget:
                case SelectionPolicy.Spread:
                    if (!(Value >= 1) || Value != System.Math.Floor(Value) || Value > int.MaxValue)
                        throw new SelectionException("probe budget " + value + " must be a whole number of at least 1");
                    break;
                case SelectionPolicy.Threshold:
                    if (!(Value >= 0 && Value <= 1))
                        throw new SelectionException("score threshold " + value + " must be between 0 and 1 (scores are remapped to [0, 1])");
                    break;
                case SelectionPolicy.Tolerance:
                    if (!(Value > 0) || double.IsInfinity(Value))
                        throw new SelectionException("tolerance " + value + " must be a mean placement error greater than 0 (0.02 ≈ 4 % relative irradiance error)");
                    break;
                default:
                    throw new SelectionException("unknown selection policy " + Policy);
            }
        }
    }
}
