using System;
using System.IO;
using Lpnn.Probes.Core;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Placement;
using Lpnn.Probes.Core.Quality;
using Lpnn.Probes.Core.Selection;
using UnityEditor;
using UnityEngine;
using Lpnn.Probes.Core.Scoring;

namespace Lpnn.Probes.Editor
{
    /// <summary>The inspector's Placement section: method and policy, the live count of what Apply would place with its
    /// estimated error, the tolerance search, the insertion ranking, and Apply / Clear / Import.</summary>
    internal sealed class PlacementPanel
    {
        private readonly PlacementPreview _preview = new PlacementPreview();
        private readonly PlacementErrorEstimate _estimate = new PlacementErrorEstimate();

        private static readonly SelectionPolicy[] PolicyOrder =
        {
            SelectionPolicy.Spread, SelectionPolicy.Percentile, SelectionPolicy.Budget, SelectionPolicy.Threshold, SelectionPolicy.Tolerance,
        };

        public void Draw(LpnnVolume volume, LpnnSession session, StepStates steps, SerializedObject edited, LpnnVolumeProperties properties,
            LpnnPipeline.StepExecutor runStep)
        {
            InspectorLayout.Header(LpnnVolumeStyles.PlacementHeader);
            InspectorLayout.Field(properties.TargetGroup);
            MethodPopup(properties.Method);
            edited.ApplyModifiedProperties();
            bool byInsertion = PlacementMethods.RanksByInsertion(volume.Method);
            bool needsScores = PlacementMethods.NeedsScores(volume.Method);
            if (!byInsertion) EditorGUILayout.HelpBox(LpnnVolumeStyles.NetworkMeasuredWorse, MessageType.None);
            var policy = PolicyPopup(properties.Policy);
            switch (policy)
            {
                case SelectionPolicy.Spread:
                case SelectionPolicy.Budget: InspectorLayout.Field(properties.Budget); break;
                case SelectionPolicy.Threshold: InspectorLayout.Field(properties.Threshold); break;
                case SelectionPolicy.Tolerance: InspectorLayout.Field(properties.Tolerance); break;
                default: InspectorLayout.Field(properties.Percentile); break;
            }
            InspectorLayout.Field(properties.KeepBoundsCorners);
            // Shown for the Network method too while it is on, so the toggle Apply's refusal names can be turned off there.
            if (byInsertion || volume.KeepPinnedProbes) InspectorLayout.Field(properties.KeepPinnedProbes);
            // The leak weighting acts through the batched refinement, so only the refined methods show the toggle.
            bool refines = PlacementMethods.RefinesInBatches(volume.Method);
            if (refines) InspectorLayout.Field(properties.AvoidLightLeaks);
            edited.ApplyModifiedProperties();
            if (byInsertion) PinButtons(volume, edited);
            // Refinement takes seconds, so the preview shows the policy's own selection and Apply refines it.
            var preview = PreviewCount(volume, session);
            var placement = steps[PipelineStep.Placement];
            long points = session.Grid != null ? session.Grid.Count : 0;
            bool rankingKnown = byInsertion && KnownInsertionRanking(volume, session) != null;
            // What Apply will cost for this many points, before it is pressed (the text and rates are Core's HeavyOperationPolicy).
            EditorGUILayout.LabelField(HeavyOperations.ApplyLine(volume, policy, points, rankingKnown, preview != null && !refines),
                EditorStyles.wordWrappedMiniLabel);
            using (new EditorGUILayout.HorizontalScope())
            {
                using (new EditorGUI.DisabledScope((needsScores && LpnnScores.For(volume).IsEmpty) || (byInsertion && session.Sh == null)))
                {
                    // Each heavy button asks HeavyOperationPolicy first; after a dialog or a long step the GUI pass ends, since the
                    // HorizontalScope's layout group is gone by then (InspectorLayout.EndGuiAfterModal, as ExportPanel does).
                    if (byInsertion && !rankingKnown && GUILayout.Button(LpnnVolumeStyles.RankByInsertion))
                    {
                        if (LpnnDialogs.ConfirmHeavy(points, "rank every point by insertion", HeavyOperation.InsertionRanking))
                            StepRunner.Run(volume, placement, (progress, cancel) => RankByInsertion(volume, session, progress, cancel));
                        InspectorLayout.EndGuiAfterModal(edited);
                    }
                    if (policy == SelectionPolicy.Tolerance && GUILayout.Button(LpnnVolumeStyles.FindProbes))
                    {
                        if (LpnnDialogs.ConfirmHeavy(points, "search the tolerance", HeavyOperations.Placement(volume, policy, true, rankingKnown)))
                            StepRunner.Run(volume, placement, (progress, cancel) => SearchTolerance(volume, session, progress, cancel));
                        InspectorLayout.EndGuiAfterModal(edited);
                    }
                    if (GUILayout.Button(LpnnVolumeStyles.Apply))
                    {
                        bool known = preview != null && !refines;
                        if (known || LpnnDialogs.ConfirmHeavy(points, "place the probes", HeavyOperations.Placement(volume, policy, false, rankingKnown)))
                            runStep(PipelineStep.Placement, (progress, cancel) =>
                                known ? LpnnPipeline.Apply(volume, session, preview) : LpnnPipeline.Apply(volume, session, progress, cancel));
                        InspectorLayout.EndGuiAfterModal(edited);
                    }
                }
                if (GUILayout.Button(LpnnVolumeStyles.Clear))
                    StepRunner.Run(volume, placement, (progress, cancel) =>
                    {
                        ProbeGroupWriter.Clear(volume.TargetGroup);
                        LeaksAtPointsInUse.Forget(volume);
                        return "probes cleared";
                    });
                if (GUILayout.Button(LpnnVolumeStyles.ImportProbes)) ImportProbes(volume, placement, edited);
            }
            InspectorLayout.Status(placement);
            AppliedLeakLine(volume, session, preview);
        }

        /// <summary>The leak line of a probe set (Documentation~/leaks.md "What is reported"): the kept report, or a button that
        /// casts the rays (seconds on large grids, with progress and cancel), beside the estimated error.</summary>
        private static void LeakLine(LpnnVolume volume, LpnnSession session, EvaluationGrid grid, int[] probes, string button)
        {
            if (session.Sh == null || session.Grid != grid) return;
            var known = LeaksAtPointsInUse.Known(volume, session, probes);
            if (known != null)
            {
                // EditorGUILayout.HelpBox: UnityCsReference Editor/Mono/EditorGUILayout.cs
                EditorGUILayout.HelpBox(known.Text, known.Failed || (known.Report != null && known.Report.Leaking > 0) ? MessageType.Warning : MessageType.Info);
                return;
            }
            // GUILayout.Button: UnityCsReference Modules/IMGUI/GUILayout.cs
            if (GUILayout.Button(button))
            {
                LeaksAtPointsInUse.Run(volume, session, grid, probes);
                // After a progress bar the layout group is gone: end this GUI pass (GUIUtility.ExitGUI: UnityCsReference
                // Modules/IMGUI/GUIUtility.cs).
                GUIUtility.ExitGUI();
            }
        }

        /// <summary>After Apply: the leak report of the placed probes when they are not the preview's (a refined placement).</summary>
        private static void AppliedLeakLine(LpnnVolume volume, LpnnSession session, SelectionResult preview)
        {
            var last = LeaksAtPointsInUse.Last(volume);
            if (last == null || last.Sh != session.Sh) return;
            if (preview != null && LeaksAtPointsInUse.Known(volume, session, preview.Indices) == last) return;
            EditorGUILayout.HelpBox("Placed probes — " + last.Text, last.Failed || (last.Report != null && last.Report.Leaking > 0) ? MessageType.Warning : MessageType.Info);
        }

        /// <summary>The policy popup in <see cref="PolicyOrder"/>, not the order of the enum, whose values are stored in scenes
        /// and only ever appended to.</summary>
        /// <summary>How many probes are pinned, and the buttons that pin the target group's probes or clear the pins (one Undo
        /// step each; Documentation~/pins.md). Apply keeps them when Keep Pinned Probes is on.</summary>
        private static void PinButtons(LpnnVolume volume, SerializedObject edited)
        {
            int pinned = volume.PinnedProbes.Length;
            using (new EditorGUILayout.HorizontalScope())
            {
                EditorGUILayout.LabelField(LpnnVolumeStyles.PinnedCount(pinned), EditorStyles.wordWrappedMiniLabel);
                using (new EditorGUI.DisabledScope(volume.TargetGroup == null))
                    if (GUILayout.Button(LpnnVolumeStyles.PinGroupButton))
                        SetPins(volume, edited, "Pin LPNN probes", GroupWorldPositions(volume.TargetGroup));
                using (new EditorGUI.DisabledScope(pinned == 0))
                    if (GUILayout.Button(LpnnVolumeStyles.ClearPinsButton))
                        SetPins(volume, edited, "Clear LPNN pins", new Vector3[0]);
            }
        }

        private static void SetPins(LpnnVolume volume, SerializedObject edited, string undoName, Vector3[] positions)
        {
            // Undo.RecordObject: Editor/Mono/Undo/Undo.bindings.cs — the pins are serialized with the volume.
            Undo.RecordObject(volume, undoName);
            volume.SetPinnedProbes(positions);
            EditorUtility.SetDirty(volume);
            edited.Update();
        }

        /// <summary>The group's probes in world space (LightProbeGroup.probePositions are local to its transform).</summary>
        private static Vector3[] GroupWorldPositions(UnityEngine.LightProbeGroup group)
        {
            var local = group.probePositions;
            var world = new Vector3[local.Length];
            for (int p = 0; p < local.Length; p++) world[p] = group.transform.TransformPoint(local[p]);
            return world;
        }

        /// <summary>The Method popup with the table's labels (Documentation~/methods.md), in the table's order: the enum lives
        /// in the engine-agnostic core, so it carries no InspectorName, and its order is its stored values'.</summary>
        private static void MethodPopup(SerializedProperty property)
        {
            // The enum is declared in value order, so its index is its value.
            var current = (PlacementMethod)property.enumValueIndex;
            int shown = 0;
            for (int i = 0; i < PlacementMethods.All.Count; i++)
                if (PlacementMethods.All[i].Method == current) shown = i;
            // EditorGUILayout.Popup: UnityCsReference Editor/Mono/EditorGUILayout.cs
            int chosen = EditorGUILayout.Popup(LpnnVolumeStyles.Method, shown, LpnnVolumeStyles.MethodLabels);
            if (chosen != shown) property.enumValueIndex = (int)PlacementMethods.All[chosen].Method;
        }

        private static SelectionPolicy PolicyPopup(SerializedProperty property)
        {
            // The enum is declared in value order, so its index is its value.
            var current = (SelectionPolicy)property.enumValueIndex;
            int shown = Math.Max(0, Array.IndexOf(PolicyOrder, current));
            // EditorGUILayout.Popup: UnityCsReference Editor/Mono/EditorGUILayout.cs
            int chosen = EditorGUILayout.Popup(LpnnVolumeStyles.Policy, shown, LpnnVolumeStyles.PolicyLabels);
            if (chosen != shown) property.enumValueIndex = (int)PolicyOrder[chosen];
            return PolicyOrder[chosen];
        }

        private static void ImportProbes(LpnnVolume volume, StepState placement, SerializedObject edited)
        {
            string path = EditorUtility.OpenFilePanel(LpnnVolumeStyles.ImportProbesPanel, LpnnPaths.DatasetFolderFor(volume), "json");
            if (!string.IsNullOrEmpty(path))
                StepRunner.Run(volume, placement, (progress, cancel) =>
                    ProbeGroupWriter.Import(volume.TargetGroup, path) + " probes imported from " + Path.GetFileName(path));
            InspectorLayout.EndGuiAfterModal(edited);
        }

        /// <summary>Shows how many probes Apply would place and their estimated error; returns the selection (null when
        /// there is none yet).</summary>
        private SelectionResult PreviewCount(LpnnVolume volume, LpnnSession session)
        {
            bool byInsertion = PlacementMethods.RanksByInsertion(volume.Method);
            var record = LpnnScores.For(volume);
            if (PlacementMethods.NeedsScores(volume.Method) && record.IsEmpty)
            {
                EditorGUILayout.HelpBox(byInsertion ? LpnnVolumeStyles.NoGuideScoresYet : LpnnVolumeStyles.NoScoresYet, MessageType.None);
                return null;
            }
            if (byInsertion && session.Sh == null)
            {
                EditorGUILayout.HelpBox(LpnnVolumeStyles.NoLightingYet, MessageType.None);
                return null;
            }
            string error;
            SelectionResult result;
            EvaluationGrid grid = null;
            Pins pins = null;
            try
            {
                grid = LpnnPipeline.PlacementGrid(volume, session);
                // The pins Apply keeps (or its refusal: the Network method, a pin outside the points), so the count is Apply's.
                pins = LpnnPipeline.PinsOf(volume, session, grid);
                if (!byInsertion)
                {
                    result = _preview.Get(grid, record, volume.GetSelectionSettings(), out error);
                }
                else
                {
                    int[] ranking = PlacementInputs.KnownInsertionRanking(session, grid, LpnnPipeline.GuideScores(volume), pins);
                    if (ranking != null)
                    {
                        result = _preview.GetRanked(grid, ranking, PlacementInputs.ValidPoints(session, grid), volume.GetSelectionSettings(), pins, out error);
                    }
                    else
                    {
                        // A tolerance search made over the order's prefixes (Find probes) is shown without the whole ranking.
                        result = _preview.Kept(grid, PlacementInputs.KnownInsertionOrder(session, grid, LpnnPipeline.GuideScores(volume), pins),
                            volume.GetSelectionSettings());
                        error = pins == null ? LpnnVolumeStyles.InsertionNotRankedYet : LpnnVolumeStyles.PinnedNotRankedYet;
                    }
                }
            }
            catch (LpnnException e)
            {
                result = null;
                error = e.Message;
            }
            if (result == null)
            {
                EditorGUILayout.HelpBox(error, MessageType.Warning);
                return null;
            }
            bool refines = PlacementMethods.RefinesInBatches(volume.Method);
            string count = (refines ? "Before refinement, Apply would place " : "Apply would place ") +
                           InvariantFormat.Count(result.Indices.Length) + " of " +
                           InvariantFormat.Count(grid.Count) + (session.InUse != null && session.InUse.Filters ? " points in use" : " points") +
                           LpnnVolumeStyles.PinnedAmong(pins == null ? 0 : pins.Count) + StepSummaries.Extras(result) + "." +
                           (refines ? "\n" + LpnnVolumeStyles.RefinedOnApply : "") +
                           (byInsertion ? InsertionValidityLine(PlacementInputs.ValidPoints(session, grid)) : ValidityLine(record));
            EditorGUILayout.HelpBox(count + "\n" + ErrorReadout(result, session, grid, out MessageType type), type);
            if (!_estimate.Has(result, session) && session.Sh != null && !PlacementErrorEstimate.IsLive(grid) && GUILayout.Button(LpnnVolumeStyles.EstimateError))
                _estimate.Get(result, session, grid, out bool _);
            LeakLine(volume, session, grid, result.Indices, LpnnVolumeStyles.FindLeaksInPreview);
            return result;
        }

        /// <summary>The insertion preview's line on invalid points: known only once the Features step ran on this grid.</summary>
        private static string InsertionValidityLine(bool[] valid)
        {
            if (valid == null) return "\n" + LpnnVolumeStyles.InsertionValidityUnknown;
            int invalid = ValidCandidates.CountInvalid(valid);
            return invalid == 0 ? "" : "\n" + InvariantFormat.Count(invalid) + " points inside geometry are never probes.";
        }

        /// <summary>The preview's line on invalid points (Documentation~/features.md "Probe validity").</summary>
        private static string ValidityLine(ScoreRecord record)
        {
            if (record.Valid == null) return "\n" + LpnnVolumeStyles.ScoresValidityUnknown;
            int invalid = record.InvalidCount;
            return invalid == 0 ? "" : "\n" + InvariantFormat.Count(invalid) + " of " + InvariantFormat.Count(record.Count) +
                                       " points are inside geometry (more than a quarter of their rays hit back faces) and are never probes.";
        }

        /// <summary>The estimated error line under the probe count: live on small grids, on request on large ones.</summary>
        private string ErrorReadout(SelectionResult result, LpnnSession session, EvaluationGrid grid, out MessageType type)
        {
            type = MessageType.Info;
            if (session.Sh == null || session.Grid != grid) return LpnnVolumeStyles.ErrorNeedsLighting;
            if (!_estimate.Has(result, session) && !PlacementErrorEstimate.IsLive(grid))
                return "Estimated error: press '" + LpnnVolumeStyles.EstimateError + "' (" + InvariantFormat.Count(grid.Count) +
                       " points is too many to follow every change).";
            string text = _estimate.Get(result, session, grid, out bool failed);
            if (failed) type = MessageType.Warning;
            return text;
        }

        private string SearchTolerance(LpnnVolume volume, LpnnSession session, ProgressCallback progress, System.Threading.CancellationToken cancel)
        {
            var grid = LpnnPipeline.PlacementGrid(volume, session);
            var settings = volume.GetSelectionSettings();
            var guide = LpnnPipeline.GuideScores(volume);
            var valid = PlacementInputs.ValidPoints(session, grid);
            var pins = LpnnPipeline.PinsOf(volume, session, grid);
            int[] ranking = PlacementInputs.KnownInsertionRanking(session, grid, guide, pins);
            var measure = ReportingMeasure.Wrap(PlacementInputs.Evaluator(session, grid), grid.Count, progress, cancel);
            // The search reads the insertion order only up to the prefixes it evaluates, as Apply does, instead of ranking
            // every point first (issue 31: ~99 rounds over up to 10⁵ probes at 10⁵ points for an answer of a few thousand).
            var result = !PlacementMethods.RanksByInsertion(volume.Method)
                ? _preview.Search(grid, LpnnScores.For(volume), settings, measure)
                : ranking != null
                    ? _preview.SearchRanked(grid, ranking, valid, settings, measure, pins)
                    : _preview.SearchPrefixes(grid, PlacementInputs.InsertionOrder(session, grid, guide, pins), valid, settings, measure, pins, progress, cancel);
            return InvariantFormat.Count(result.Indices.Length) + " probes are within the tolerance" + StepSummaries.Extras(result);
        }

        /// <summary>The insertion ranking of the current lighting (guided by the stored scores for Guided insertion; from the
        /// pinned probes when the volume keeps them) if already computed (never computes during a repaint).</summary>
        private static int[] KnownInsertionRanking(LpnnVolume volume, LpnnSession session)
        {
            try
            {
                var grid = LpnnPipeline.PlacementGrid(volume, session);
                return PlacementInputs.KnownInsertionRanking(session, grid, LpnnPipeline.GuideScores(volume), LpnnPipeline.PinsOf(volume, session, grid));
            }
            catch (LpnnException)
            {
                return null;
            }
        }

        private static string RankByInsertion(LpnnVolume volume, LpnnSession session, ProgressCallback progress, System.Threading.CancellationToken cancel)
        {
            var grid = LpnnPipeline.PlacementGrid(volume, session);
            float[] guide = LpnnPipeline.GuideScores(volume);
            var pins = LpnnPipeline.PinsOf(volume, session, grid);
            PlacementInputs.RankByInsertion(session, grid, progress, cancel, guide, pins);
            return InvariantFormat.Count(grid.Count) + " points ranked by " + (guide == null ? "insertion" : "guided insertion") +
                   (pins == null ? "" : " from " + LpnnVolumeStyles.PinnedCount(pins.Count));
        }
    }
}
