using System.Threading;
using Lpnn.Probes.Core;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Selection;
using UnityEditor;
using NumericsVector3 = System.Numerics.Vector3;

namespace Lpnn.Probes.Editor
{
    /// <summary>The pipeline steps of one volume, shared by the inspector, batch mode, the demo and the tests:
    /// grid → lighting → features → scores → selection → LightProbeGroup. Every algorithm is the core's; this class
    /// only connects it to Unity. Each step publishes its result at the end, so a cancel or an error keeps the
    /// previous state. Each returns the one-line summary the inspector shows.</summary>
    public static class LpnnPipeline
    {
        /// <summary>Points above which the inspector asks before running a heavy step.</summary>
        public const int LargeGridWarning = 250_000;

        public static string BuildGrid(LpnnVolume volume, LpnnSession session)
        {
            var boxes = volume.GetWorldBoxes();
            var grid = GridBuilder.Build(boxes, volume.CellSize, volume.PointLimit);
            session.SetGrid(grid, GridSignature.Of(boxes, volume.CellSize));
            return InvariantFormat.Count(grid.Count) + " evaluation points, about " +
                   Megabytes(EvaluationGrid.EstimateBytes(grid.Count, FeatureExtractor.Schema.Count)) + " through the pipeline";
        }

        public static string SampleLighting(LpnnVolume volume, LpnnSession session, bool sceneBakeAllowed, ProgressCallback progress,
            CancellationToken cancel)
        {
            using (var lighting = EvaluationLighting.Create(volume, sceneBakeAllowed))
                return SampleLighting(volume, session, lighting, progress, cancel);
        }

        /// <summary>Samples with a given lighting implementation (the tests pass an analytic one).</summary>
        public static string SampleLighting(LpnnVolume volume, LpnnSession session, IEvaluationLighting lighting, ProgressCallback progress,
            CancellationToken cancel)
        {
            var grid = FreshGrid(volume, session);
            float[] sh = lighting.Sample(grid, progress, cancel);
            session.SetLighting(sh, lighting.Description);
            return "SH at " + InvariantFormat.Count(grid.Count) + " points, " + lighting.Description;
        }

        /// <param name="warning">Set when static geometry without colliders was invisible to the rays.</param>
        public static string ExtractFeatures(LpnnVolume volume, LpnnSession session, ProgressCallback progress, CancellationToken cancel,
            out string warning)
        {
            var grid = FreshGrid(volume, session);
            if (session.Sh == null) throw new LpnnException("there is no lighting data for this grid; run the Lighting data step first");
            FeatureSet features;
            using (var physics = new RaycastScope(volume, volume.AddTemporaryColliders))
            {
                features = FeatureExtractor.Extract(grid, session.Sh, new PhysicsRaycaster(), progress, cancel);
                warning = physics.Uncovered.Count == 0 ? "" :
                    physics.Uncovered.Count + " static renderers have no collider (e.g. '" + physics.Uncovered[0].name +
                    "'), so the rays passed through them; add colliders or enable 'Add Temporary Colliders'";
            }
            session.SetFeatures(features);
            int invalid = ValidCandidates.CountInvalid(ValidCandidates.FromBackFaceFractions(features.BackFaceFractions));
            return InvariantFormat.Count(features.PointCount) + " × " + features.Schema.Count + " features (" + features.Schema.Id + ")" + InvalidNote(invalid);
        }

        public static string Score(LpnnVolume volume, LpnnSession session)
        {
            var grid = FreshGrid(volume, session);
            if (session.Features == null || session.Features.PointCount != grid.Count)
                throw new LpnnException("there are no features for this grid; run the Features step first");
            // Points inside geometry never reach the network (it was trained on clouds without them) and get score 0;
            // fewer than 4 non-coplanar valid points stop here with what to do.
            bool[] valid = ValidCandidates.FromBackFaceFractions(session.Features.BackFaceFractions);
            ValidCandidates.Check(grid, valid);
            var outcome = LpnnScoring.Score(volume, session, ValidCandidates.ValidRows(session.Features, valid), grid.CellSize);
            float[] scores = ValidCandidates.Scatter(outcome.Scores, valid);
            string model = volume.Model != null ? volume.Model.name : "";
            // Undo.RecordObject: Editor/Mono/Undo/Undo.bindings.cs — scores are serialized with the volume.
            Undo.RecordObject(volume, "Score LPNN evaluation points");
            volume.LastScores.Set(grid.CopyIds(), scores, grid.CellSize, outcome.DeviceName, model, valid);
            // On a prefab instance a direct field write is lost at the next prefab reload unless recorded as an override
            // (UnityCsReference Editor/Mono/Prefabs/PrefabUtility.bindings.cs RecordPrefabInstancePropertyModifications).
            PrefabUtility.RecordPrefabInstancePropertyModifications(volume);
            EditorUtility.SetDirty(volume);
            // The spread ranking (behind the default Tolerance policy and Spread) costs O(N log N): computed here, under the step's progress bar, rather
            // than on the inspector's first repaint.
            var policy = volume.GetSelectionSettings().Policy;
            if (policy == SelectionPolicy.Spread || policy == SelectionPolicy.Tolerance)
            {
                int[] computedNow = PlacementInputs.Scored(grid, volume.LastScores).SpreadOrder;
            }
            return InvariantFormat.Count(outcome.Scores.Length) + " scores on " + outcome.DeviceName + InvalidNote(volume.LastScores.InvalidCount) +
                   (outcome.Fallback.Length > 0 ? " (after: " + outcome.Fallback + ")" : "");
        }

        /// <summary>The selection the current settings give (the volume's method: the last scores, or the insertion ranking).</summary>
        public static SelectionResult Select(LpnnVolume volume, LpnnSession session)
        {
            SelectedPositions(volume, session, out var selection);
            return selection;
        }

        /// <summary>World positions of the probes the current settings select: on the last scores (Network), or on the
        /// insertion ranking of the Lighting step's SH (Insertion, computed on first use). The tolerance policy measures
        /// placement errors against that SH with Unity's tetrahedralisation.</summary>
        public static NumericsVector3[] SelectedPositions(LpnnVolume volume, LpnnSession session, out SelectionResult selection) =>
            SelectedPositions(volume, session, null, CancellationToken.None, out selection);

        public static NumericsVector3[] SelectedPositions(LpnnVolume volume, LpnnSession session, ProgressCallback progress, CancellationToken cancel,
            out SelectionResult selection)
        {
            var grid = PlacementGrid(volume, session);
            var settings = volume.GetSelectionSettings();
            var measure = settings.Policy == SelectionPolicy.Tolerance ? PlacementInputs.Evaluator(session, grid) : null;
            selection = PlacementMethods.NeedsScores(volume.Method)
                ? ProbeSelector.Select(PlacementInputs.Scored(grid, volume.LastScores), settings, measure)
                : ProbeSelector.SelectFromRanking(grid, PlacementInputs.RankByInsertion(session, FreshLitGrid(volume, session), progress, cancel), settings, measure,
                    PlacementInputs.ValidPoints(session, grid));
            return PositionsOf(grid, selection);
        }

        /// <summary>Writes the selected probes into the target LightProbeGroup (one Undo step).</summary>
        public static string Apply(LpnnVolume volume, LpnnSession session) => Apply(volume, session, null, CancellationToken.None);

        public static string Apply(LpnnVolume volume, LpnnSession session, ProgressCallback progress, CancellationToken cancel)
        {
            SelectedPositions(volume, session, progress, cancel, out var selection);
            return Apply(volume, session, selection);
        }

        /// <summary>Writes a selection already made on the scored grid (e.g. the inspector's tolerance search) into the
        /// target LightProbeGroup (one Undo step).</summary>
        public static string Apply(LpnnVolume volume, LpnnSession session, SelectionResult selection)
        {
            var grid = PlacementGrid(volume, session);
            var positions = PositionsOf(grid, selection);
            ProbeGroupWriter.Apply(volume.TargetGroup, positions, "Place LPNN probes");
            return positions.Length + " probes placed" + Extras(selection);
        }

        private static NumericsVector3[] PositionsOf(EvaluationGrid grid, SelectionResult selection)
        {
            var positions = new NumericsVector3[selection.Indices.Length];
            for (int p = 0; p < positions.Length; p++) positions[p] = grid.GetPosition(selection.Indices[p]);
            return positions;
        }

        /// <summary>", N inside geometry (never probes)" when some points are invalid.</summary>
        public static string InvalidNote(int invalid) =>
            invalid == 0 ? "" : ", " + InvariantFormat.Count(invalid) + " inside geometry (never probes)";

        public static string Extras(SelectionResult selection)
        {
            string text = "";
            if (selection.CornersAdded > 0) text += ", " + selection.CornersAdded + " box corners";
            if (selection.AddedForTetrahedron > 0) text += ", " + selection.AddedForTetrahedron + " added to form a tetrahedron";
            string extras = text.Length == 0 ? "" : " (incl." + text.Substring(1) + ")";
            if (selection.Tolerance != null)
                extras += "; mean error " + InvariantFormat.Number(System.Math.Round(selection.Tolerance.MeanError, 4)) + " after " +
                          selection.Tolerance.Evaluated.Count + " evaluations";
            return extras;
        }

        /// <summary>The session's grid when it still matches the volume; otherwise an error saying to rebuild it.</summary>
        public static EvaluationGrid FreshGrid(LpnnVolume volume, LpnnSession session)
        {
            if (session.Grid == null) throw new LpnnException("there is no evaluation grid yet; run the Volume step (Build grid) first");
            if (session.GridSignature != GridSignature.Of(volume))
                throw new LpnnException("the boxes, the transform or the cell size changed since the grid was built; build the grid again");
            return session.Grid;
        }

        /// <summary>The grid the volume's method places on: the scored grid (Network) or the session's lit grid (Insertion).</summary>
        public static EvaluationGrid PlacementGrid(LpnnVolume volume, LpnnSession session) =>
            PlacementMethods.NeedsScores(volume.Method) ? ScoredGrid(volume, session) : FreshLitGrid(volume, session);

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
            var record = volume.LastScores;
            if (record.IsEmpty) throw new LpnnException("the volume has no scores yet; run the Scoring step first");
            var grid = session.Grid != null && session.GridSignature == GridSignature.Of(volume) ? session.Grid : null;
            if (grid == null)
            {
                var boxes = volume.GetWorldBoxes();
                grid = GridBuilder.Build(boxes, volume.CellSize, volume.PointLimit);
                session.SetGrid(grid, GridSignature.Of(boxes, volume.CellSize));
            }
            if (session.ScoresVerifiedForGrid == record.Scores) return grid;
            if (!SameIds(grid, record.Ids))
                throw new LpnnException("the stored scores belong to another grid (" + InvariantFormat.Count(record.Count) + " points at cell size " +
                                        InvariantFormat.Number(record.CellSize) + "); the volume changed since scoring: run Lighting, Features and Scoring again");
            session.ScoresVerifiedForGrid = record.Scores;
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

        public static string Megabytes(long bytes) => InvariantFormat.Number(System.Math.Round(bytes / 1048576.0, 1)) + " MB";
    }
}
