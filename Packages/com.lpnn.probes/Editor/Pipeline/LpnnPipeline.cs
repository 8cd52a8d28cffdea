using System;
using System.Collections.Generic;
using System.Threading;
using Lpnn.Probes.Core;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.InUse;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Pipeline;
using Lpnn.Probes.Core.Quality;
using Lpnn.Probes.Core.Scoring;
using Lpnn.Probes.Core.Selection;
using UnityEditor;
using NumericsVector3 = System.Numerics.Vector3;

namespace Lpnn.Probes.Editor
{
    /// <summary>The pipeline steps of one volume, shared by the inspector, batch mode, the demo and the tests:
    /// grid → lighting → features → scores → selection → LightProbeGroup. <see cref="Run"/> is the one place that says
    /// which steps run in which order. Every algorithm is the core's; this class only connects it to Unity. Each step
    /// publishes its result at the end, so a cancel or an error keeps the previous state, and returns what it produced
    /// as data (<see cref="StepResult"/>); how that is said to the user is the inspector's and the batch log's business.</summary>
    public static class LpnnPipeline
    {
        /// <summary>One step's work, given progress reporting and cancellation.</summary>
        public delegate StepResult StepWork(ProgressCallback progress, CancellationToken cancel);

        /// <summary>Runs one step's work the caller's way (progress bar, timing, error display) and says whether to go on.</summary>
        public delegate bool StepExecutor(PipelineStep step, StepWork work);

        /// <summary>Runs the steps the volume's method needs, in order, from the grid up to and including
        /// <paramref name="until"/>, each through <paramref name="execute"/>; stops at the first step it reports as failed.
        /// <paramref name="createLighting"/> gives the lighting the Lighting step samples (disposed after it).</summary>
        /// <returns>True when every step ran.</returns>
        public static bool Run(LpnnVolume volume, LpnnSession session, PipelineStep until, Func<LpnnVolume, IEvaluationLighting> createLighting,
            StepExecutor execute)
        {
            // No target group: fail the Placement step now, through the caller's error display, not after minutes of work.
            if (until >= PipelineStep.Placement && volume.TargetGroup == null)
                return execute(PipelineStep.Placement, (progress, cancel) => { ProbeGroupWriter.RequireTarget(volume.TargetGroup); return null; });
            for (var next = PipelineStep.Grid; next <= until; next++)
            {
                var step = next;
                if (!IsNeeded(volume, step)) continue;
                if (!execute(step, (progress, cancel) => RunStep(step, volume, session, createLighting, progress, cancel))) return false;
            }
            return true;
        }

        /// <summary>Whether the volume's method needs the step. Features run for every method: their rays tell which points
        /// lie inside geometry (never probes); only the Network and Guided insertion methods need scores (plain insertion
        /// ranks by the lighting alone).</summary>
        public static bool IsNeeded(LpnnVolume volume, PipelineStep step) =>
            step != PipelineStep.Scoring || PlacementMethods.NeedsScores(volume.Method);

        private static StepResult RunStep(PipelineStep step, LpnnVolume volume, LpnnSession session, Func<LpnnVolume, IEvaluationLighting> createLighting,
            ProgressCallback progress, CancellationToken cancel)
        {
            switch (step)
            {
                case PipelineStep.Grid:
                    return BuildGrid(volume, session, progress, cancel);
                case PipelineStep.Lighting:
                    using (var lighting = createLighting(volume))
                        return SampleLighting(volume, session, lighting, progress, cancel);
                case PipelineStep.Features:
                    return ExtractFeatures(volume, session, progress, cancel);
                case PipelineStep.Scoring:
                    return Score(volume, session);
                case PipelineStep.Placement:
                    return Apply(volume, session, progress, cancel);
                default:
                    throw new ArgumentOutOfRangeException(nameof(step), step, "not a pipeline step");
            }
        }

        public static GridResult BuildGrid(LpnnVolume volume, LpnnSession session) => BuildGrid(volume, session, null, CancellationToken.None);

        /// <summary>The grid of the volume's boxes with the in-use rule applied (Documentation~/in-use.md): for Band and
        /// Reachable only the points in use are kept, so lighting, features, scoring and every placement method work on them
        /// alone; for All every point is kept and the session remembers which are in use, for the reports. The rule's rays
        /// report progress and cancel between batches.</summary>
        public static GridResult BuildGrid(LpnnVolume volume, LpnnSession session, ProgressCallback progress, CancellationToken cancel)
        {
            var all = GridBuilder.Build(volume.GetWorldBoxes(), volume.CellSize, volume.PointLimit);
            var inUse = VolumeInUse.Compute(volume, all, progress, cancel);
            var grid = inUse.Filters ? inUse.AllPoints.Subset(inUse.InUseOfAll) : all;
            session.SetGrid(grid, GridSignature.Of(volume), inUse);
            return new GridResult(grid, inUse);
        }

        public static LightingResult SampleLighting(LpnnVolume volume, LpnnSession session, bool sceneBakeAllowed, ProgressCallback progress,
            CancellationToken cancel)
        {
            using (var lighting = EvaluationLighting.Create(volume, sceneBakeAllowed))
                return SampleLighting(volume, session, lighting, progress, cancel);
        }

        /// <summary>Samples with a given lighting implementation (the tests pass an analytic one).</summary>
        public static LightingResult SampleLighting(LpnnVolume volume, LpnnSession session, IEvaluationLighting lighting, ProgressCallback progress,
            CancellationToken cancel)
        {
            var grid = FreshGrid(volume, session);
            float[] sh = lighting.Sample(grid, progress, cancel);
            session.SetLighting(sh, lighting.Description);
            return new LightingResult(grid.Count, lighting.Description);
        }

        public static FeaturesResult ExtractFeatures(LpnnVolume volume, LpnnSession session, ProgressCallback progress, CancellationToken cancel)
        {
            var grid = FreshGrid(volume, session);
            FeatureSet features;
            var uncovered = new List<string>();
            using (var physics = new RaycastScope(volume, volume.AddTemporaryColliders))
            {
                // The rays see meshes from inside (back faces); the overlap query sees the solid colliders rays started in
                // cannot (Core.Features.InsideColliders).
                var scene = volume.gameObject.scene;
                features = ApplySteps.ExtractFeatures(grid, session.Sh, new PhysicsRaycaster(scene), new PhysicsColliderQuery(scene), progress, cancel);
                foreach (var renderer in physics.Uncovered) uncovered.Add(renderer.name);
            }
            session.SetFeatures(features);
            int invalid = ValidCandidates.CountInvalid(ApplySteps.ValidPoints(features));
            return new FeaturesResult(features, invalid, uncovered);
        }

        public static ScoringResult Score(LpnnVolume volume, LpnnSession session)
        {
            var grid = FreshGrid(volume, session);
            if (session.Features == null || session.Features.PointCount != grid.Count)
                throw new LpnnException("there are no features for this grid; run the Features step first");
            // Points inside geometry never reach the network (it was trained on clouds without them) and get score 0;
            // fewer than 4 non-coplanar valid points stop here with what to do.
            bool[] valid = ApplySteps.ValidPoints(session.Features);
            ValidCandidates.Check(grid, valid);
            var outcome = LpnnScoring.Score(volume, session, ValidCandidates.ValidRows(session.Features, valid), grid.CellSize);
            float[] scores = ValidCandidates.Scatter(outcome.Scores, valid);
            string model = volume.Model != null ? volume.Model.name : "";
            // The scores are editor data outside the volume (LpnnScores: session + Library, issue 31): nothing is written
            // into the scene or a prefab override, so scoring neither dirties the scene nor records an Undo step.
            var record = new ScoreRecord();
            record.Set(grid.CopyIds(), scores, grid.CellSize, outcome.DeviceName, model, valid);
            record.SetGridSignature(session.GridSignature);
            LpnnScores.Store(volume, record);
            // The spread ranking (behind the default Tolerance policy and Spread) costs O(N log N): computed here, under the
            // step's progress bar, rather than on the inspector's first repaint (the Network method's; guided insertion only
            // reads the scores as its guide).
            var policy = volume.GetSelectionSettings().Policy;
            if (!PlacementMethods.RanksByInsertion(volume.Method) && (policy == SelectionPolicy.Spread || policy == SelectionPolicy.Tolerance))
                PlacementInputs.ComputeSpreadOrder(grid, record);
            return new ScoringResult(outcome, record.InvalidCount);
        }

        /// <summary>The selection the current settings give (the volume's method: the last scores, or the insertion ranking,
        /// guided by the last scores for Guided insertion).</summary>
        public static SelectionResult Select(LpnnVolume volume, LpnnSession session)
        {
            SelectedPositions(volume, session, out var selection);
            return selection;
        }

        /// <summary>World positions of the probes the current settings select: on the last scores (Network), or on the
        /// insertion ranking of the Lighting step's SH (Insertion; guided by the last scores for Guided insertion; computed
        /// as far as the policy reads it). The tolerance policy measures placement errors against that SH with Unity's
        /// tetrahedralisation.</summary>
        public static NumericsVector3[] SelectedPositions(LpnnVolume volume, LpnnSession session, out SelectionResult selection) =>
            SelectedPositions(volume, session, null, CancellationToken.None, out selection);

        public static NumericsVector3[] SelectedPositions(LpnnVolume volume, LpnnSession session, ProgressCallback progress, CancellationToken cancel,
            out SelectionResult selection)
        {
            var grid = PlacementGrid(volume, session);
            var settings = volume.GetSelectionSettings();
            // Each tolerance-search evaluation reports progress and honours cancel (Core.Selection.ReportingMeasure).
            var measure = settings.Policy == SelectionPolicy.Tolerance
                ? ReportingMeasure.Wrap(PlacementInputs.Evaluator(session, grid), grid.Count, progress, cancel)
                : null;
            var pins = PinsOf(volume, session, grid);
            selection = PlacementMethods.RanksByInsertion(volume.Method)
                ? SelectByInsertion(volume, session, grid, GuideScores(volume), settings, measure, PlacementMethods.RefinesInBatches(volume.Method), progress, cancel, pins)
                : ProbeSelector.Select(PlacementInputs.Scored(grid, LpnnScores.For(volume)), settings, measure);
            return ApplySteps.PositionsOf(grid, selection, pins);
        }

        /// <summary>The insertion methods' selection, reading the insertion order (guided by <paramref name="guideScores"/> when
        /// given) only as far as the policy needs (a budget's points, the tolerance search's prefixes), or the whole ranking
        /// when it is already known; with <paramref name="refine"/>, refined in batches from two to three times its count of the ranking
        /// (Core.Quality.RefinedSelection, quality.md §5.3) — leak-aware when the volume avoids light leaks (Documentation~/leaks.md):
        /// the refinement's segment tests are physics casts in the volume's scene, as the Features step and the leak report cast.</summary>
        private static SelectionResult SelectByInsertion(LpnnVolume volume, LpnnSession session, EvaluationGrid grid, float[] guideScores,
            SelectionSettings settings, IPlacementErrorMeasure measure, bool refine, ProgressCallback progress, CancellationToken cancel, Pins pins)
        {
            // The step itself is the core's (Core.Pipeline.ApplySteps), so the editor-free rehearsal runs this code.
            bool[] valid = PlacementInputs.ValidPoints(session, grid);
            // With pins the order starts from them: the kept pinned order (the one the preview and Rank by insertion read),
            // reused however far it was computed, as the pin-free one is.
            int[] known = PlacementInputs.KnownInsertionRanking(session, grid, guideScores, pins);
            var order = known == null ? PlacementInputs.InsertionOrder(session, grid, guideScores, pins) : null;
            var evaluator = refine ? PlacementInputs.Evaluator(session, grid) : null;
            if (!(refine && volume.AvoidLightLeaks))
                return ApplySteps.SelectByInsertion(grid, valid, known, order, settings, measure, refine, evaluator, progress, cancel, pins);
            using (new RaycastScope(volume, volume.AddTemporaryColliders))
            {
                var rays = new PhysicsRaycaster(volume.gameObject.scene);
                return ApplySteps.SelectByInsertion(grid, valid, known, order, settings, measure, refine, evaluator, progress, cancel, pins,
                    ApplySteps.LeakWeightingOf(volume.AvoidLightLeaks, rays));
            }
        }

        /// <summary>The volume's pinned probes snapped to <paramref name="grid"/>'s valid points (Documentation~/pins.md), or null
        /// when it keeps none. The Network method cannot keep them: an error says to choose an insertion method. Core's
        /// Pins.KeptBy decides, for Apply, the inspector's preview and batch mode alike.</summary>
        internal static Pins PinsOf(LpnnVolume volume, LpnnSession session, EvaluationGrid grid) =>
            PlacementInputs.KeptPins(session, grid, volume.Method, volume.KeepPinnedProbes, volume.PinnedProbes);

        /// <summary>The scores that guide the volume's insertion ranking: the stored scores for Guided insertion (valid on the
        /// grid <see cref="PlacementGrid"/> returned), else null (plain insertion, or the Network method).</summary>
        public static float[] GuideScores(LpnnVolume volume) => PlacementMethods.GuidesInsertion(volume.Method) ? LpnnScores.For(volume).Scores : null;

        /// <summary>Writes the selected probes into the target LightProbeGroup (one Undo step).</summary>
        public static PlacementResult Apply(LpnnVolume volume, LpnnSession session) => Apply(volume, session, null, CancellationToken.None);

        public static PlacementResult Apply(LpnnVolume volume, LpnnSession session, ProgressCallback progress, CancellationToken cancel)
        {
            ProbeGroupWriter.RequireTarget(volume.TargetGroup);  // before the ranking, search and refinement, not after them
            SelectedPositions(volume, session, progress, cancel, out var selection);
            return Apply(volume, session, selection);
        }

        /// <summary>Writes a selection already made on the scored grid (e.g. the inspector's tolerance search) into the
        /// target LightProbeGroup (one Undo step).</summary>
        public static PlacementResult Apply(LpnnVolume volume, LpnnSession session, SelectionResult selection)
        {
            var grid = PlacementGrid(volume, session);
            var positions = ApplySteps.PositionsOf(grid, selection, PinsOf(volume, session, grid));
            ProbeGroupWriter.Apply(volume.TargetGroup, positions, "Place LPNN probes");
            string unknown;
            var errorAtPointsInUse = ErrorAtPointsInUseOf(session, grid, selection, out unknown);
            return new PlacementResult(positions, selection, errorAtPointsInUse, unknown);
        }

        /// <summary>The placed probes' error at the points in use (one evaluation with Unity's tetrahedralisation against the
        /// Lighting step's SH): for Band and Reachable over the grid, which holds only them; for All over the session's mask.
        /// Null with the reason when there is no lighting for this grid or the points in use are unknown.</summary>
        internal static ErrorAtPointsInUse ErrorAtPointsInUseOf(LpnnSession session, EvaluationGrid grid, SelectionResult selection, out string unknown)
        {
            if (session.Sh == null || session.Grid != grid)
            {
                unknown = "error at the points in use: n/a (no lighting for this grid: run the Lighting data step)";
                return null;
            }
            if (session.InUse == null || !session.InUse.Known)
            {
                unknown = ErrorAtPointsInUse.Unknown(session.InUse);
                return null;
            }
            try
            {
                unknown = "";
                return ErrorAtPointsInUse.Of(PlacementInputs.Evaluator(session, grid).Evaluate(selection.Indices), session.InUse);
            }
            catch (LpnnException e)
            {
                // The probes are written already; a set Unity cannot tetrahedralise (e.g. fewer than 4) has no error to show.
                unknown = "error at the points in use: n/a (" + e.Message + ")";
                return null;
            }
        }


        /// <summary>The session's grid when it still matches the volume; otherwise an error saying to rebuild it.</summary>
        public static EvaluationGrid FreshGrid(LpnnVolume volume, LpnnSession session)
        {
            if (session.Grid == null) throw new LpnnException("there is no evaluation grid yet; run the Volume step (Build grid) first");
            if (session.GridSignature != GridSignature.Of(volume))
                throw new LpnnException("the boxes, the transform, the cell size or the in-use settings changed since the grid was built; build the grid again");
            return session.Grid;
        }

        /// <summary>The grid the volume's method places on: the scored grid (Network), the session's lit grid (Insertion), or
        /// the session's lit grid whose ids the stored scores were made for (Guided insertion).</summary>
        public static EvaluationGrid PlacementGrid(LpnnVolume volume, LpnnSession session)
        {
            if (!PlacementMethods.RanksByInsertion(volume.Method)) return ScoredGrid(volume, session);
            var grid = FreshLitGrid(volume, session);
            // The lit grid is the session's fresh grid, so ScoredGrid returns it after checking the scores' ids against it.
            if (PlacementMethods.NeedsScores(volume.Method)) ScoredGrid(volume, session);
            return grid;
        }

        /// <summary>The session's grid with its lighting (what the insertion method ranks), or an error saying which step to run.</summary>
        public static EvaluationGrid FreshLitGrid(LpnnVolume volume, LpnnSession session)
        {
            var grid = FreshGrid(volume, session);
            if (session.Sh == null)
                throw new LpnnException("the insertion method ranks points by the lighting at every evaluation point, and there is none for this grid: " +
                                        "run the Lighting data step (or choose the Network method)");
            return grid;
        }

        /// <summary>The grid the stored scores belong to: the session's, or one rebuilt from the current boxes (after a
        /// domain reload) when its ids are exactly the scored ids.</summary>
        public static EvaluationGrid ScoredGrid(LpnnVolume volume, LpnnSession session)
        {
            var record = LpnnScores.For(volume);
            if (record.IsEmpty) throw new LpnnException("the volume has no scores yet; run the Scoring step first");
            string signature = GridSignature.Of(volume);
            var grid = session.Grid != null && session.GridSignature == signature ? session.Grid : null;
            if (grid == null)
            {
                if (record.GridSignature.Length > 0 && record.GridSignature != signature) throw ScoredOnAnotherGrid(record);
                grid = RebuildScoredGrid(volume, session, record, signature);
            }
            if (session.ScoresVerifiedForGrid == record.Scores) return grid;
            if (!SameIds(grid, record.Ids)) throw ScoredOnAnotherGrid(record);
            session.ScoresVerifiedForGrid = record.Scores;
            return grid;
        }

        private static LpnnException ScoredOnAnotherGrid(ScoreRecord record) =>
            new LpnnException("the stored scores belong to another grid (" + InvariantFormat.Count(record.Count) + " points at cell size " +
                              InvariantFormat.Number(record.CellSize) + "); the volume changed since scoring: build the grid and run Lighting, " +
                              "Features and Scoring again");

        /// <summary>The scored grid without its session (after a script reload): every point of the current boxes (All), or
        /// those of them the scores were stored for (Band, Reachable: the in-use points when scored, found again without
        /// casting the rule's rays; the stored signature says the settings are the same). All's report mask is not kept
        /// across a reload: the error at the points in use shows again once the grid is built again.</summary>
        private static EvaluationGrid RebuildScoredGrid(LpnnVolume volume, LpnnSession session, ScoreRecord record, string signature)
        {
            var all = GridBuilder.Build(volume.GetWorldBoxes(), volume.CellSize, volume.PointLimit);
            var grid = all;
            InUsePoints inUse = null;
            if (volume.InUseRule != InUseRule.All)
            {
                var scored = new bool[all.Count];
                var ids = record.Ids;
                for (int n = 0; n < record.Count; n++)
                {
                    int index = all.IndexOf(new LatticeId(ids[3 * n], ids[3 * n + 1], ids[3 * n + 2]));
                    if (index < 0) throw ScoredOnAnotherGrid(record);
                    scored[index] = true;
                }
                grid = all.Subset(scored);
                inUse = new InUsePoints(volume.InUseRule, volume.InUseRule, null, 0, "the stored scores", all, scored, "");
            }
            session.SetGrid(grid, signature, inUse);
            return grid;
        }

        private static bool SameIds(EvaluationGrid grid, int[] ids)
        {
            if (ids.Length != 3 * grid.Count) return false;
            for (int n = 0; n < grid.Count; n++)
            {
                var id = grid.GetId(n);
                if (id.I != ids[3 * n] || id.J != ids[3 * n + 1] || id.K != ids[3 * n + 2]) return false;
            }
            return true;
        }
    }
}
