using System.Collections.Generic;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Selection;
using NumericsVector3 = System.Numerics.Vector3;

namespace Lpnn.Probes.Editor
{
    /// <summary>What a pipeline step produced, as data: the inspector, batch mode and the tests each say it in their own
    /// words (the inspector's and the batch log's sentences are in StepSummaries).</summary>
    public abstract class StepResult
    {
        public abstract PipelineStep Step { get; }
    }

    public sealed class GridResult : StepResult
    {
        public override PipelineStep Step => PipelineStep.Grid;
        public EvaluationGrid Grid { get; }
        /// <summary>The in-use rule's outcome (null when the grid was built without it).</summary>
        internal InUsePoints InUse { get; }
        public GridResult(EvaluationGrid grid) { Grid = grid; }
        internal GridResult(EvaluationGrid grid, InUsePoints inUse) : this(grid) { InUse = inUse; }
    }

    public sealed class LightingResult : StepResult
    {
        public override PipelineStep Step => PipelineStep.Lighting;
        public int PointCount { get; }
        /// <summary>Which lighting was sampled (EvaluationLighting's description).</summary>
        public string Source { get; }
        public LightingResult(int pointCount, string source) { PointCount = pointCount; Source = source ?? ""; }
    }

    public sealed class FeaturesResult : StepResult
    {
        public override PipelineStep Step => PipelineStep.Features;
        public FeatureSet Features { get; }
        /// <summary>Points inside geometry (never probes, features.md "Probe validity").</summary>
        public int InvalidCount { get; }
        /// <summary>Static renderers without a collider, which the rays passed through.</summary>
        public IReadOnlyList<string> RenderersWithoutColliders { get; }

        public FeaturesResult(FeatureSet features, int invalidCount, IReadOnlyList<string> renderersWithoutColliders)
        {
            Features = features;
            InvalidCount = invalidCount;
            RenderersWithoutColliders = renderersWithoutColliders ?? new string[0];
        }
    }

    public sealed class ScoringResult : StepResult
    {
        public override PipelineStep Step => PipelineStep.Scoring;
        public ScoreOutcome Outcome { get; }
        public int InvalidCount { get; }
        public ScoringResult(ScoreOutcome outcome, int invalidCount) { Outcome = outcome; InvalidCount = invalidCount; }
    }

    public sealed class PlacementResult : StepResult
    {
        public override PipelineStep Step => PipelineStep.Placement;
        /// <summary>World positions of the probes written into the target group.</summary>
        public NumericsVector3[] Positions { get; }
        public SelectionResult Selection { get; }
        /// <summary>The placed probes' error at the points in use; null when unknown (no lighting, or the points in use unknown:
        /// <see cref="ErrorAtPointsInUseUnavailable"/> says why).</summary>
        internal ErrorAtPointsInUse ErrorAtPointsInUse { get; }
        internal string ErrorAtPointsInUseUnavailable { get; } = "";
        public PlacementResult(NumericsVector3[] positions, SelectionResult selection) { Positions = positions; Selection = selection; }

        internal PlacementResult(NumericsVector3[] positions, SelectionResult selection, ErrorAtPointsInUse errorAtPointsInUse, string unavailable)
            : this(positions, selection)
        {
            ErrorAtPointsInUse = errorAtPointsInUse;
            ErrorAtPointsInUseUnavailable = unavailable ?? "";
        }
    }
}
