using System;
using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Core.Selection
{
    /// <summary>The importance weights of the spread ranking (Documentation~/selection.md, "Spread ranking" step 1):
    /// w = (s / median(s))^0.5 with s the score clipped to [1e-6, 1]. Relative to the median so that the weights do
    /// not depend on how confident the model is overall; the square root so that a point ten times as important is
    /// taken at about three times the distance, not ten (scores concentrate the probes; spread keeps them apart).</summary>
    internal static class SpreadWeights
    {
        /// <summary>Scores below this (and NaN) count as this: a weight of zero would never pick the point, and every
        /// point must appear in a full ranking.</summary>
        public const double ScoreFloor = 1e-6;

        public const double ScoreCeiling = 1.0;

        public static double[] Compute(float[] scores)
        {
            if (scores == null) throw new ArgumentNullException(nameof(scores));
            var clipped = new double[scores.Length];
            for (int n = 0; n < scores.Length; n++) clipped[n] = Clip(scores[n]);
            var weights = new double[scores.Length];
            if (scores.Length == 0) return weights;
            double median = Statistics.Median(clipped);
            // median ≥ ScoreFloor > 0, so the division is always defined; sqrt is the correctly rounded x^0.5.
            for (int n = 0; n < weights.Length; n++) weights[n] = Math.Sqrt(clipped[n] / median);
            return weights;
        }

        /// <summary>The score in double, clipped to [1e-6, 1]; NaN → 1e-6 (+∞ → 1, −∞ → 1e-6).</summary>
        public static double Clip(float score)
        {
            if (float.IsNaN(score)) return ScoreFloor;
            double s = score;
            if (s < ScoreFloor) return ScoreFloor;
            return s > ScoreCeiling ? ScoreCeiling : s;
        }
    }
}
