using Lpnn.Probes.Core.InUse;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Quality;

namespace Lpnn.Probes.Editor
{
    /// <summary>The irradiance error of a placement at the points in use (Documentation~/in-use.md): the figure `lpnn place`
    /// reports as the error at in-use points, shown by the inspector and the batch log for every rule, also All, so the
    /// dilution of the mean by the air stays visible.</summary>
    internal sealed class ErrorAtPointsInUse
    {
        /// <summary>Mean and 95th percentile over the points in use.</summary>
        public ErrorSummary Summary { get; }
        public int Points { get; }
        /// <summary>The rule the points are in use by (for All: the report rule).</summary>
        public InUseRule Rule { get; }

        public ErrorAtPointsInUse(ErrorSummary summary, int points, InUseRule rule)
        {
            Summary = summary;
            Points = points;
            Rule = rule;
        }

        /// <summary>The error at the points in use of <paramref name="result"/> (a placement on the session's grid), or null
        /// when which points are in use is unknown.</summary>
        public static ErrorAtPointsInUse Of(PlacementErrorResult result, InUsePoints inUse)
        {
            if (inUse == null || !inUse.Known) return null;
            if (inUse.Filters) return new ErrorAtPointsInUse(result.Irradiance, result.PointIrradiance.Length, inUse.MaskRule);
            return new ErrorAtPointsInUse(ErrorSummary.Of(result.PointIrradiance, inUse.InUseOfAll), inUse.InUseCount, inUse.MaskRule);
        }

        /// <summary>"error at the 1,234 points in use (reachable): 0.043 mean, 0.12 at the 95th percentile".</summary>
        public string Describe() =>
            "error at the " + InvariantFormat.Count(Points) + " points in use (" + InUseRules.Name(Rule) + "): " + Round(Summary.Mean) + " mean, " +
            Round(Summary.P95) + " at the 95th percentile";

        /// <summary>The sentence for a placement whose points in use are unknown.</summary>
        public static string Unknown(InUsePoints inUse) =>
            inUse == null ? "error at the points in use: n/a (build the grid again to apply the in-use rule)"
                : "error at the points in use: n/a (" + inUse.Unavailable + ")";

        private static string Round(double value) => InvariantFormat.Number(System.Math.Round(value, 4));
    }
}
