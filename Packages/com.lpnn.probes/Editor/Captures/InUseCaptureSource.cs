using Lpnn.Probes.Core.Captures;
using Lpnn.Probes.Core.InUse;
using Lpnn.Probes.Core.Json;

namespace Lpnn.Probes.Editor
{
    /// <summary>What a capture records of the in-use rule (Documentation~/in-use.md "What placement does with the mask"): the
    /// rule and its parameters in `source`, and for All the `in_use` section (uint8 [N], 1 = in use by the report rule,
    /// named by `source.in_use_report_rule`). Band and Reachable captures hold the in-use points only.</summary>
    internal static class InUseCaptureSource
    {
        public const string Section = "in_use";

        /// <summary>Writes the rule's keys into <paramref name="source"/> and returns <paramref name="capture"/> with the
        /// `in_use` section for All (when its mask is known). A session without the rule's outcome (a grid set from code)
        /// records nothing, as a capture from before the rule.</summary>
        public static Capture Record(Capture capture, JsonValue source, InUsePoints inUse)
        {
            if (inUse == null) return capture;
            source.Set("in_use", JsonValue.From(InUseRules.Name(inUse.Rule)));
            if (inUse.Parameters != null)
            {
                source.Set("in_use_band_height", JsonValue.From(inUse.Parameters.BandHeight));
                source.Set("in_use_slope_limit", JsonValue.From(inUse.Parameters.SlopeLimitDegrees));
                source.Set("in_use_step_height", JsonValue.From(inUse.Parameters.StepHeight));
            }
            source.Set("in_use_seeds", JsonValue.From(inUse.SeedCount));
            source.Set("points_before_in_use", JsonValue.From(inUse.PointsBefore));
            if (inUse.Filters || !inUse.Known) return capture;
            source.Set("in_use_report_rule", JsonValue.From(InUseRules.Name(inUse.MaskRule)));
            var flags = new byte[inUse.InUseOfAll.Length];
            for (int p = 0; p < flags.Length; p++) flags[p] = inUse.InUseOfAll[p] ? (byte)1 : (byte)0;
            return capture.WithSection(new CaptureSection(Section, "uint8", new[] { flags.Length }, flags));
        }
    }
}
