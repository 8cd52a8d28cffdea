using System;
using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Core.InUse
{
    /// <summary>The band height H, slope limit θ and step height s of Documentation~/in-use.md "Parameters" (metres and
    /// degrees), checked on construction as Python's InUseParameters checks them.</summary>
    internal sealed class InUseParameters
    {
        public const double DefaultBandHeight = 3.0;
        public const double DefaultSlopeLimitDegrees = 45.0;
        public const double DefaultStepHeight = 0.5;
        public const double MaxBandHeight = 1e4;
        public const double MaxSlopeLimitDegrees = 90.0;
        public const double MaxStepHeight = 1e4;
        /// <summary>Metres per floor-profile interval of a horizontal move: M = ceil(h / 0.25), within [1, 64].</summary>
        public const double ProfileInterval = 0.25;
        public const int MaxProfileIntervals = 64;

        public double BandHeight { get; }
        public double SlopeLimitDegrees { get; }
        public double StepHeight { get; }

        public InUseParameters(double bandHeight = DefaultBandHeight, double slopeLimitDegrees = DefaultSlopeLimitDegrees,
            double stepHeight = DefaultStepHeight)
        {
            BandHeight = Checked("band_height", bandHeight, 0, MaxBandHeight, true, false, "metres", DefaultBandHeight);
            SlopeLimitDegrees = Checked("slope_limit_degrees", slopeLimitDegrees, 0, MaxSlopeLimitDegrees, false, true, "degrees",
                DefaultSlopeLimitDegrees);
            StepHeight = Checked("step_height", stepHeight, 0, MaxStepHeight, false, false, "metres", DefaultStepHeight);
        }

        /// <summary>cos θ: a floor is walkable when |n_y| ≥ this. Degrees × (π / 180), as Python's math.radians.</summary>
        public double WalkableCosine => Math.Cos(SlopeLimitDegrees * (Math.PI / 180.0));

        /// <summary>s + (h/M)·tan θ: the largest rise over one floor-profile interval of a horizontal move.</summary>
        public double RiseLimit(double cellSize) =>
            StepHeight + cellSize / ProfileIntervals(cellSize) * Math.Tan(SlopeLimitDegrees * (Math.PI / 180.0));

        /// <summary>M = min(64, max(1, ⌈h / 0.25⌉)): the floor-profile intervals of a horizontal move.</summary>
        public static int ProfileIntervals(double cellSize) =>
            (int)Math.Min(MaxProfileIntervals, Math.Max(1.0, Math.Ceiling(cellSize / ProfileInterval)));

        private static double Checked(string name, double value, double low, double high, bool lowOpen, bool highOpen, string unit,
            double defaultValue)
        {
            bool inside = Double3.IsFiniteNumber(value) && (lowOpen ? value > low : value >= low) && (highOpen ? value < high : value <= high);
            if (inside) return value;
            throw new InUseException("in-use " + name + " " + InvariantFormat.Number(value) + " is out of range; use a finite number in " +
                                     (lowOpen ? "(" : "[") + InvariantFormat.Number(low) + ", " + InvariantFormat.Number(high) +
                                     (highOpen ? ")" : "]") + " " + unit + " (default " + InvariantFormat.Number(defaultValue) + ")");
        }
    }
}
