using System;
using System.Collections.Generic;
using System.Numerics;
using System.Threading;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Quality;
using Lpnn.Probes.Core.Selection;
using Lpnn.Probes.Core.Sh;

namespace Lpnn.Probes.Core.Pipeline
{
    /// <summary>Where the Apply step's probes go: a LightProbeGroup in the editor (one Undo step), a recording fake in the
    /// rehearsal (Tests/Core/ApplyRehearsalTests.cs). Called once, with the final positions, only when nothing was cancelled.</summary>
    internal interface IProbeGroupWriter
    {
        void Write(Vector3[] positions);
    }

    /// <summary>The Features step of a grid and its lighting (the editor: FeatureExtractor.Extract with Unity's physics
    /// raycaster; the rehearsal: the features of a capture).</summary>
    internal delegate FeatureSet FeatureStep(EvaluationGrid grid, float[] sh, ProgressCallback progress, CancellationToken cancel);

    /// <summary>The order of the Apply steps between Unity calls (Documentation~/index.md "Apply rehearsal"): lighting through
    /// an <see cref="ILightSampler"/> (<see cref="SampleLighting"/>) → features (<see cref="ExtractFeatures"/>: the rays and the
    /// solid colliders) → valid points (<see cref="ValidPoints"/>) → the insertion selection with the tolerance policy and the
    /// batched refinement (<see cref="SelectByInsertion"/>) → the positions handed to an <see cref="IProbeGroupWriter"/>. The
    /// editor's <c>LpnnPipeline</c> runs these same methods for its Features and Placement steps (its lighting implementations
    /// sample through <see cref="FeatureExtractor.SampleLighting"/>, as <see cref="SampleLighting"/> does); <see cref="Rehearse"/>
    /// chains them the way <c>LpnnPipeline.Run</c> does, and <see cref="Place"/> is the Placement step alone (the inspector's
    /// Apply), both publishing into an <see cref="ApplyState"/> that stands in for the editor's session, so they run under Mono.
    /// Every step honours <c>cancel</c>; a cancel throws <see cref="OperationCanceledException"/> before the writer is called
    /// and before the cancelled step publishes anything.</summary>
    internal static class ApplySteps
    {
        public const string LightingStage = FeatureExtractor.LightingStage;

        /// <summary>The Lighting step: the SH at every grid point, in batches with progress and cancel, every value checked finite
        /// (<see cref="FeatureExtractor.SampleLighting"/>, which the editor's lighting implementations call too).</summary>
        public static float[] SampleLighting(EvaluationGrid grid, ILightSampler lighting, ProgressCallback progress, CancellationToken cancel)
        {
            if (lighting == null) throw new ArgumentNullException(nameof(lighting));
            return FeatureExtractor.SampleLighting(grid, lighting, progress, cancel);
        }

        /// <summary>The Features step (the editor's LpnnPipeline.ExtractFeatures): the lpnn.features.v1 matrix and each point's
        /// back-face fraction from <paramref name="raycaster"/>'s rays, the points inside solid colliders of
        /// <paramref name="colliders"/> (null: none) made invalid (features.md "Probe validity").</summary>
        public static FeatureSet ExtractFeatures(EvaluationGrid grid, float[] sh, IRaycaster raycaster, IColliderQuery colliders, ProgressCallback progress,
            CancellationToken cancel)
        {
            if (grid == null) throw new ArgumentNullException(nameof(grid));
            if (sh == null) throw new LpnnException("there is no lighting data for this grid; run the Lighting data step first");
            if (raycaster == null) throw new ArgumentNullException(nameof(raycaster));
            return FeatureExtractor.Extract(grid, sh, raycaster, colliders, progress, cancel);
        }

        /// <summary>The Features step as a <see cref="FeatureStep"/> (the rehearsal's: a raycaster and collider query of a test scene).</summary>
        public static FeatureStep Features(IRaycaster raycaster, IColliderQuery colliders) =>
            (grid, sh, progress, cancel) => ExtractFeatures(grid, sh, raycaster, colliders, progress, cancel);

        /// <summary>Which points may become probes: those the Features step found outside geometry; null (every point) when
        /// there are no features or they carry no back-face fractions (a capture's).</summary>
        public static bool[] ValidPoints(FeatureSet features) =>
            features == null || features.BackFaceFractions == null ? null : ValidCandidates.FromBackFaceFractions(features.BackFaceFractions);

        /// <summary>The insertion methods' selection, reading the insertion order only as far as the policy needs (a budget's
        /// points, the tolerance search's prefixes), or the whole ranking when it is already known (<paramref name="known"/>,
        /// else <paramref name="order"/>); with <paramref name="refine"/>, refined in batches from two to three times its count of the
        /// ranking (Core.Quality.RefinedSelection, quality.md §5.3) with <paramref name="evaluator"/>. <paramref name="pins"/> (null:
        /// none; Documentation~/pins.md): the order must start with them (InsertionOrder.OfValid with the same pins); the
        /// selection holds every pin (a tolerance search that stops below the pins' count gets the rest added), a count
        /// policy's count must hold them, and the refinement keeps them. <paramref name="leaks"/> (null: leak-blind; the
        /// volume's "Avoid light leaks", Documentation~/leaks.md): the refinement is the leak-aware one, its segment tests cast
        /// through the weighting's raycaster (the volume's physics in the editor); without <paramref name="refine"/> it has
        /// nothing to act on.</summary>
        public static SelectionResult SelectByInsertion(EvaluationGrid grid, bool[] valid, int[] known, InsertionOrder order, SelectionSettings settings,
            IPlacementErrorMeasure measure, bool refine, PlacementEvaluator evaluator, ProgressCallback progress, CancellationToken cancel, Pins pins = null,
            LeakWeighting leaks = null)
        {
            if (grid == null) throw new ArgumentNullException(nameof(grid));
            RankingPrefix prefix;
            int candidates;
            SelectionResult selection;
            if (known != null)
            {
                candidates = valid == null ? grid.Count : grid.Count - ValidCandidates.CountInvalid(valid);
                // The editor keeps the order's own ranking (InsertionOrder.All): the valid points only — with pins, only those
                // not blocked — so shorter than the grid whenever a point is invalid or blocked; a ranking of every grid point
                // (InsertionRanking.RankValid) is taken too, without its invalid tail. Read as prefixes, as the lazy order is.
                int[] ranking = valid != null && known.Length == grid.Count ? ValidCandidates.Filter(known, valid) : known;
                if (pins != null && !pins.Heads(ranking))
                    throw new PinException("the insertion ranking was made without these " + InvariantFormat.Count(pins.Count) + " pinned probes " +
                                           "(it does not start with them): rank the points again with the pins (Rank by insertion)");
                prefix = count => ranking;
                selection = ProbeSelector.SelectFromPrefixes(grid, candidates, prefix, settings, measure, valid);
            }
            else
            {
                if (order == null) throw new ArgumentNullException(nameof(order), "neither a known ranking nor an insertion order");
                candidates = order.Count;
                prefix = count => order.Prefix(count, progress, cancel);
                selection = ProbeSelector.SelectFromPrefixes(grid, order.Count, prefix, settings, measure, valid);
            }
            if (pins != null)
            {
                // The policy's own count holds the pins (what the artist asked for, as `lpnn place` checks it), not the
                // completed selection, which the bounds corners or the tetrahedron guarantee may have grown past it.
                if (settings.Policy != SelectionPolicy.Tolerance) pins.CheckCount(PolicyCount(settings, candidates));
                selection = WithPins(selection, pins);
            }
            if (!refine) return selection;
            return RefinedSelection.Refine(grid, selection, prefix, candidates, settings, evaluator, leaks, valid, progress, cancel, pins);
        }

        /// <summary>The leak weighting an Apply's refinement uses (Documentation~/leaks.md "A leak-aware default"): the default
        /// weight over <paramref name="rays"/> (the volume's physics in the editor) when the volume avoids light leaks, else
        /// null (the leak-blind refinement, the volume's opt-out).</summary>
        public static LeakWeighting LeakWeightingOf(bool avoidLightLeaks, IRaycaster rays) => avoidLightLeaks ? new LeakWeighting(rays) : null;

        /// <summary>The inspector's preview of the insertion methods (Documentation~/pins.md "Where"): the selection Apply makes
        /// before its refinement — the one it writes when Refine in batches is off — from the whole insertion ranking already
        /// computed (<paramref name="ranking"/>; never runs an insertion round, so a repaint stays fast). With
        /// <paramref name="pins"/> the ranking must be the one made with them (<see cref="InsertionOrder.OfValid"/> with the pins):
        /// the pins head it, count in the policy's probes (a budget below them is a <see cref="PinException"/>), and no point
        /// within the keep distance of one is a new probe. The Tolerance policy has no preview here: its search measures the
        /// error many times (<see cref="SelectByInsertion"/> with a measure: the inspector's Find probes).</summary>
        public static SelectionResult PreviewByInsertion(EvaluationGrid grid, bool[] valid, int[] ranking, SelectionSettings settings, Pins pins)
        {
            if (ranking == null) throw new ArgumentNullException(nameof(ranking), "the preview needs the insertion ranking (Rank by insertion)");
            if (settings.Policy == SelectionPolicy.Tolerance)
                throw new SelectionException("the tolerance policy measures the placement error of many probe counts, which a preview does not: " +
                                             "run the search (Find probes) or Apply");
            return SelectByInsertion(grid, valid, ranking, null, settings, null, false, null, null, CancellationToken.None, pins);
        }

        /// <summary>The probes a count policy keeps of <paramref name="candidates"/> before the completion (as
        /// ProbeSelector reads the ranking's head): PercentileCount for Percentile, the budget (at most the candidates) otherwise.</summary>
        private static int PolicyCount(SelectionSettings settings, int candidates) =>
            settings.Policy == SelectionPolicy.Percentile
                ? ProbeSelector.PercentileCount(settings.Value, candidates)
                : (int)Math.Min(settings.Value, candidates);

        /// <summary>The selection with every pin it lacks added (sorted indices, as the selector returns them).</summary>
        internal static SelectionResult WithPins(SelectionResult selection, Pins pins)
        {
            var all = new SortedSet<int>(selection.Indices);
            all.UnionWith(pins.Indices);
            if (all.Count == selection.Indices.Length) return selection;
            var indices = new int[all.Count];
            all.CopyTo(indices);
            return new SelectionResult(indices, selection.CornersAdded, selection.AddedForTetrahedron, selection.Tolerance, selection.RefinedFrom);
        }

        /// <summary>World positions of the selected grid points, in the selection's order; a pinned point is written at the
        /// artist's own position (pins.md), not at the evaluation point it stands for.</summary>
        public static Vector3[] PositionsOf(EvaluationGrid grid, SelectionResult selection, Pins pins)
        {
            var positions = PositionsOf(grid, selection);
            if (pins == null) return positions;
            var pinOf = new Dictionary<int, int>();
            for (int p = 0; p < pins.Count; p++) pinOf[pins.Indices[p]] = p;
            for (int k = 0; k < positions.Length; k++)
                if (pinOf.TryGetValue(selection.Indices[k], out int p))
                    positions[k] = new Vector3((float)pins.Positions[p].X, (float)pins.Positions[p].Y, (float)pins.Positions[p].Z);
            return positions;
        }

        /// <summary>World positions of the selected grid points, in the selection's order.</summary>
        public static Vector3[] PositionsOf(EvaluationGrid grid, SelectionResult selection)
        {
            var positions = new Vector3[selection.Indices.Length];
            for (int p = 0; p < positions.Length; p++) positions[p] = grid.GetPosition(selection.Indices[p]);
            return positions;
        }

        /// <summary>The whole Apply of the plain Insertion method (the volume's default: Insertion, Refine in batches) on a
        /// grid — the inspector's Run all steps: <paramref name="lighting"/> samples the SH, <paramref name="features"/> gives the
        /// features (their back-face fractions say which points are valid), <paramref name="tetrahedralizer"/> stands in for
        /// Unity's, and the positions go to <paramref name="writer"/> only after every step finished uncancelled. Each step
        /// publishes its result into <paramref name="state"/> (null: a fresh one) only when it completed, as the editor's
        /// steps do into the session: a cancel leaves the previous state. <paramref name="leakRays"/> (null: leak-blind): the
        /// scene's rays for the leak-aware refinement, what a volume that avoids light leaks (its default) refines with.</summary>
        public static SelectionResult Rehearse(EvaluationGrid grid, ILightSampler lighting, FeatureStep features, ITetrahedralizer tetrahedralizer,
            SelectionSettings settings, bool refine, IProbeGroupWriter writer, ProgressCallback progress, CancellationToken cancel, ApplyState state = null,
            IRaycaster leakRays = null) =>
            Rehearse(grid, lighting, features, tetrahedralizer, settings, refine, writer, progress, cancel, state, LeakWeightingOf(leakRays != null, leakRays));

        /// <summary>As the public <see cref="Rehearse(EvaluationGrid, ILightSampler, FeatureStep, ITetrahedralizer, SelectionSettings, bool, IProbeGroupWriter, ProgressCallback, CancellationToken, ApplyState, IRaycaster)"/>,
        /// with the refinement's leak weighting given (null: leak-blind): the Apply benchmark's switch between remembering
        /// segments and casting them anew.</summary>
        internal static SelectionResult Rehearse(EvaluationGrid grid, ILightSampler lighting, FeatureStep features, ITetrahedralizer tetrahedralizer,
            SelectionSettings settings, bool refine, IProbeGroupWriter writer, ProgressCallback progress, CancellationToken cancel, ApplyState state,
            LeakWeighting leaks)
        {
            if (grid == null) throw new ArgumentNullException(nameof(grid));
            if (writer == null) throw new ArgumentNullException(nameof(writer));
            if (features == null) throw new ArgumentNullException(nameof(features));
            state = state ?? new ApplyState();
            cancel.ThrowIfCancellationRequested();
            // Lighting step (LpnnPipeline.SampleLighting).
            var sh = SampleLighting(grid, lighting, progress, cancel);
            cancel.ThrowIfCancellationRequested();
            state.PublishLighting(grid, sh);
            // Features step (LpnnPipeline.ExtractFeatures); its back-face fractions make the valid points (PlacementInputs.ValidPoints).
            var set = features(grid, sh, progress, cancel);
            cancel.ThrowIfCancellationRequested();
            state.PublishFeatures(set);
            // Placement step (LpnnPipeline.Apply).
            return Place(state, tetrahedralizer, settings, refine, writer, progress, cancel, leaks);
        }

        /// <summary>The Placement step alone on what <paramref name="state"/> holds (the inspector's Apply: LpnnPipeline.Apply →
        /// SelectedPositions → SelectByInsertion, with PlacementInputs' kept insertion order, reused however far an earlier —
        /// possibly cancelled — run computed it). Writes once, at the end. <paramref name="leakRays"/>: as for <see cref="Rehearse"/>.</summary>
        public static SelectionResult Place(ApplyState state, ITetrahedralizer tetrahedralizer, SelectionSettings settings, bool refine,
            IProbeGroupWriter writer, ProgressCallback progress, CancellationToken cancel, IRaycaster leakRays = null) =>
            Place(state, tetrahedralizer, settings, refine, writer, progress, cancel, LeakWeightingOf(leakRays != null, leakRays));

        /// <summary>As the public Place, with the refinement's leak weighting given (null: leak-blind).</summary>
        internal static SelectionResult Place(ApplyState state, ITetrahedralizer tetrahedralizer, SelectionSettings settings, bool refine,
            IProbeGroupWriter writer, ProgressCallback progress, CancellationToken cancel, LeakWeighting leaks)
        {
            if (state == null) throw new ArgumentNullException(nameof(state));
            if (writer == null) throw new ArgumentNullException(nameof(writer));
            if (state.Grid == null || state.Sh == null)
                throw new LpnnException("the insertion method ranks points by the lighting at every evaluation point, and there is none for this grid: " +
                                        "run the Lighting data step");
            cancel.ThrowIfCancellationRequested();
            var grid = state.Grid;
            bool[] valid = ValidPoints(state.Features);
            var evaluator = new PlacementEvaluator(state.Reference, tetrahedralizer);
            var order = state.InsertionOrder(tetrahedralizer);
            var measure = settings.Policy == SelectionPolicy.Tolerance ? ReportingMeasure.Wrap(evaluator, grid.Count, progress, cancel) : null;
            var selection = SelectByInsertion(grid, valid, null, order, settings, measure, refine, evaluator, progress, cancel, null, leaks);
            cancel.ThrowIfCancellationRequested();
            writer.Write(PositionsOf(grid, selection));
            return selection;
        }
    }
}
