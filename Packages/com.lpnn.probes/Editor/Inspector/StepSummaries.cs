using System;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Selection;

namespace Lpnn.Probes.Editor
{
    /// <summary>The sentences the inspector's ✓ lines and the batch log use for what a step produced. Kept out of the
    /// pipeline, which returns data (<see cref="StepResult"/>).</summary>
    public static class StepSummaries
    {
        /// <summary>The one-line summary of a step's result.</summary>
        public static string Describe(StepResult result)
        {
            // (if-chains, not a switch on types: the Mono compiler that checks this code has no switch type patterns)
            if (result is GridResult grid)
                return InvariantFormat.Count(grid.Grid.Count) + " evaluation points, about " +
                       Megabytes(EvaluationGrid.EstimateBytes(grid.Grid.Count, FeatureExtractor.Schema.Count)) + " through the pipeline" +
                       (grid.InUse == null ? "" : "; " + grid.InUse.Describe());
            if (result is LightingResult lighting)
                return "SH at " + InvariantFormat.Count(lighting.PointCount) + " points, " + lighting.Source;
            if (result is FeaturesResult features)
                return InvariantFormat.Count(features.Features.PointCount) + " × " + features.Features.Schema.Count + " features (" +
                       features.Features.Schema.Id + ")" + InvalidNote(features.InvalidCount) +
                       (features.Features.InsideColliderCount > 0
                           ? " (" + InvariantFormat.Count(features.Features.InsideColliderCount) + " of them inside solid colliders)"
                           : "");
            if (result is ScoringResult scoring)
                return InvariantFormat.Count(scoring.Outcome.Scores.Length) + " scores on " + scoring.Outcome.DeviceName + InvalidNote(scoring.InvalidCount) +
                       (scoring.Outcome.Fallback.Length > 0 ? " (after: " + scoring.Outcome.Fallback + ")" : "");
            if (result is PlacementResult placement)
                return placement.Positions.Length + " probes placed" + Extras(placement.Selection) + "; " +
                       (placement.ErrorAtPointsInUse != null ? placement.ErrorAtPointsInUse.Describe() : placement.ErrorAtPointsInUseUnavailable);
            throw new ArgumentException("no summary for " + (result == null ? "null" : result.GetType().Name), nameof(result));
        }

        /// <summary>A caveat about a successful result ("" when there is none).</summary>
        public static string Warning(StepResult result)
        {
            var grid = result as GridResult;
            if (grid != null && grid.InUse != null && !grid.InUse.Known)
                return "the error at the points in use cannot be reported: " + grid.InUse.Unavailable;
            var features = result as FeaturesResult;
            if (features == null || features.RenderersWithoutColliders.Count == 0) return "";
            return features.RenderersWithoutColliders.Count + " static renderers have no collider (e.g. '" + features.RenderersWithoutColliders[0] +
                   "'), so the rays passed through them; add colliders or enable 'Add Temporary Colliders'";
        }

        /// <summary>", N inside geometry (never probes)" when some points are invalid.</summary>
        public static string InvalidNote(int invalid) =>
            invalid == 0 ? "" : ", " + InvariantFormat.Count(invalid) + " inside geometry (never probes)";

        /// <summary>What a selection added beyond its policy's points, and the tolerance search's outcome.</summary>
        public static string Extras(SelectionResult selection)
        {
            string text = "";
            if (selection.CornersAdded > 0) text += ", " + selection.CornersAdded + " box corners";
            if (selection.AddedForTetrahedron > 0) text += ", " + selection.AddedForTetrahedron + " added to form a tetrahedron";
            string extras = text.Length == 0 ? "" : " (incl." + text.Substring(1) + ")";
            if (selection.RefinedFrom > 0) extras += "; refined in batches from " + InvariantFormat.Count(selection.RefinedFrom) + " probes";
            if (selection.Tolerance != null)
                extras += (selection.RefinedFrom > 0 ? " (the tolerance search kept " + InvariantFormat.Count(selection.Tolerance.Count) + " at mean error " : "; mean error ") +
                          InvariantFormat.Number(Math.Round(selection.Tolerance.MeanError, 4)) + " after " +
                          selection.Tolerance.Evaluated.Count + " evaluations" + (selection.RefinedFrom > 0 ? ")" : "");
            return extras;
        }

        public static string Megabytes(long bytes) => InvariantFormat.Number(Math.Round(bytes / 1048576.0, 1)) + " MB";
    }
}
