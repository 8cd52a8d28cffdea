using System;
using System.Collections.Generic;
using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Core.Scoring
{
    /// <summary>Which inference backend the user asked for. Values are stored in scenes (Unity serializes the number), so
    /// new preferences are only ever appended.</summary>
    public enum ScoringBackendPreference
    {
        /// <summary>GPU compute when the machine has compute shaders, otherwise CPU; CPU again if the GPU run fails.</summary>
        Auto = 0,
        /// <summary>GPU compute only (an error where compute shaders are missing).</summary>
        Gpu = 1,
        /// <summary>CPU only: deterministic and available everywhere, including batch mode with -nographics.</summary>
        Cpu = 2,
    }

    /// <summary>A backend actually tried.</summary>
    public enum ScoringDevice
    {
        GpuCompute,
        Cpu = 2,
    }

    /// <summary>The engine-agnostic decisions around running the model (Documentation~/model-contract.md): which
    /// backends to try in which order, the input shape, the point-count guard and the output check. The Sentis calls
    /// themselves live in the editor assembly.</summary>
    internal static class ScoringPlan
    {
        /// <summary>Points scored in one pass unless the caller sets another limit. The network pools over the whole
        /// cloud, so a grid cannot be split into chunks without changing its scores; activations grow with the point
        /// count (hundreds of floats per point per layer), which this bound keeps within a desktop GPU's memory.</summary>
        public const int DefaultMaxPoints = 1000000;

        /// <summary>Backends to try, in order. Auto falls back to the CPU when the GPU run throws.</summary>
        public static IReadOnlyList<ScoringDevice> Attempts(ScoringBackendPreference preference, bool supportsComputeShaders)
        {
            switch (preference)
            {
                case ScoringBackendPreference.Cpu:
                    return new[] { ScoringDevice.Cpu };
                case ScoringBackendPreference.Gpu:
                    if (!supportsComputeShaders)
                        throw new ScoringException("the GPU backend was requested, but this machine reports no compute shader support " +
                                                     "(e.g. batch mode with -nographics); choose Auto or CPU");
                    return new[] { ScoringDevice.GpuCompute };
                default:
                    return supportsComputeShaders ? new[] { ScoringDevice.GpuCompute, ScoringDevice.Cpu } : new[] { ScoringDevice.Cpu };
            }
        }

        /// <summary>The model input shape [1, N, F] (one cloud per batch entry), after the point-count guard.</summary>
        public static int[] InputShape(int pointCount, int featureCount, double cellSize, int maxPoints = DefaultMaxPoints)
        {
            CheckPointCount(pointCount, cellSize, maxPoints);
            if (featureCount < 1) throw new ArgumentOutOfRangeException(nameof(featureCount), featureCount, "need at least one feature");
            if ((long)pointCount * featureCount > int.MaxValue)
                throw new ScoringException(InvariantFormat.Count(pointCount) + " points × " + featureCount +
                                             " features exceed the largest tensor the inference engine can hold; use a larger cell size");
            return new[] { 1, pointCount, featureCount };
        }

        /// <summary>Refuses to score more than <paramref name="maxPoints"/> points, suggesting the cell size that fits.</summary>
        public static void CheckPointCount(int pointCount, double cellSize, int maxPoints = DefaultMaxPoints)
        {
            if (maxPoints < 1) throw new ArgumentOutOfRangeException(nameof(maxPoints), maxPoints, "the scoring limit must be at least 1");
            if (pointCount < 1) throw new ScoringException("there are no evaluation points to score; build the grid first");
            if (pointCount <= maxPoints) return;
            string suggestion = cellSize > 0 && !double.IsInfinity(cellSize)
                ? "use a cell size of about " + InvariantFormat.Number(InvariantFormat.RoundUpSignificant(cellSize * Math.Pow((double)pointCount / maxPoints, 1.0 / 3.0), 3)) +
                  " or larger (now " + InvariantFormat.Number(cellSize) + "), shrink the boxes, or raise the scoring point limit"
                : "use a larger cell size, shrink the boxes, or raise the scoring point limit";
            throw new ScoringException(
                "the grid has " + InvariantFormat.Count(pointCount) + " evaluation points, but scoring runs on at most " +
                InvariantFormat.Count(maxPoints) + " in one pass (the network pools over the whole cloud, so it cannot be split); " + suggestion);
        }

        /// <summary>The model must return exactly one importance per point (output [1, N]).</summary>
        public static float[] CheckOutput(float[] output, int pointCount, string modelName)
        {
            int length = output?.Length ?? 0;
            if (length != pointCount)
                throw new ScoringException("the model '" + modelName + "' returned " + InvariantFormat.Count(length) + " values for " +
                                             InvariantFormat.Count(pointCount) + " points; its output '" + ModelCard.ContractOutputName +
                                             "' must have shape [batch, points]: re-export it with `lpnn export`");
            return output;
        }
    }
}
