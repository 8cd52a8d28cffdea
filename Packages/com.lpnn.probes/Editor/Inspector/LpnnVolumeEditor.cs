using System;
using System.Collections.Generic;
using System.IO;
using Lpnn.Probes.Core;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Scoring;
using Lpnn.Probes.Core.Selection;
using UnityEditor;
using UnityEngine;

namespace Lpnn.Probes.Editor
{
    /// <summary>The LPNN volume inspector, in the order of the thesis' panel (§3.5): Volume, Lighting data, Features,
    /// Scoring, Placement, Capture export. Settings are edited through SerializedProperty (Undo and prefab overrides
    /// for free: UnityCsReference Editor/Mono/SerializedObject.bindings.cs); each step shows its state, last duration
    /// and last error. The work itself is in <see cref="LpnnPipeline"/>.</summary>
    [CustomEditor(typeof(LpnnVolume))]
    public sealed class LpnnVolumeEditor : UnityEditor.Editor
    {
        private readonly LpnnBoxHandles _boxHandles = new LpnnBoxHandles();
        private readonly PlacementPreview _preview = new PlacementPreview();
        private readonly PlacementErrorEstimate _estimate = new PlacementErrorEstimate();
        private string _countSignature;
        private string _countText;
        private MessageType _countType;
        private long _countedPoints;
        private int _uncoveredMeshes = -1;
        private TextAsset _checkedCard;
        private UnityEngine.Object _checkedModel;
        private IReadOnlyList<ModelCheck> _modelChecks = new ModelCheck[0];

        private LpnnVolume Volume => (LpnnVolume)target;
        private LpnnSession Session => LpnnSession.For(Volume);
        private StepStates Steps => StepStates.For(Volume);

        /// <summary>Points above which the inspector asks before running a heavy step.</summary>
        private const int LargeGridWarning = 250_000;

        private void OnEnable()
        {
            _uncoveredMeshes = ColliderAudit.StaticMeshesWithoutColliders().Count;
        }

        public override void OnInspectorGUI()
        {
            serializedObject.Update();
            Steps.DropStale(Session, Volume);
            EditorGUILayout.HelpBox("Places light probes where baked lighting needs them: build the grid, get the lighting at every " +
                                    "point, extract features, score them with the model, then place the best points as probes.", MessageType.None);
            if (GUILayout.Button("Run all steps")) RunAll();
            VolumeSection();
            LightingSection();
            FeaturesSection();
            ScoringSection();
            PlacementSection();
            ExportSection();
            serializedObject.ApplyModifiedProperties();
        }

        private void OnSceneGUI()
        {
            if (!Volume.ShowGizmos) return;
            // The serialized copy may be stale (an inspector edit, an Undo, a script): read it before the handles edit it, as
            // OnInspectorGUI does (UnityCsReference Editor/Mono/SerializedObject.bindings.cs Update).
            serializedObject.Update();
            _boxHandles.Draw(Volume, serializedObject);
        }

        // ------------------------------------------------------------------------------------------ sections

        private void VolumeSection()
        {
            Header("1. Volume");
            Field(LpnnVolume.Fields.Boxes);
            Field(LpnnVolume.Fields.CellSize);
            Field(LpnnVolume.Fields.PointLimit);
            Field(LpnnVolume.Fields.ShowGizmos);
            serializedObject.ApplyModifiedProperties();
            UpdatePointCount();
            EditorGUILayout.HelpBox(_countText, _countType);
            if (GUILayout.Button("Build grid") && ConfirmHeavy("build the grid"))
                RunStep(PipelineStep.Grid, (progress, cancel) => LpnnPipeline.BuildGrid(Volume, Session));
            Status(Steps[PipelineStep.Grid]);
        }

        private void LightingSection()
        {
            Header("2. Lighting data");
            Field(LpnnVolume.Fields.LightingSource);
            serializedObject.ApplyModifiedProperties();
            EditorGUILayout.HelpBox(EvaluationLighting.Explain(Volume), MessageType.Info);
            using (new EditorGUI.DisabledScope(Session.Grid == null))
            {
                if (GUILayout.Button("Sample lighting") && ConfirmHeavy("sample the lighting"))
                {
                    bool bake = !EvaluationLighting.RewritesSceneLighting(Volume) || ConfirmSceneBake();
                    if (bake)
                        RunStep(PipelineStep.Lighting, (progress, cancel) => LpnnPipeline.SampleLighting(Volume, Session, true, progress, cancel));
                }
            }
            Status(Steps[PipelineStep.Lighting]);
        }

        private void FeaturesSection()
        {
            Header("3. Features");
            Field(LpnnVolume.Fields.AddTemporaryColliders);
            serializedObject.ApplyModifiedProperties();
            if (_uncoveredMeshes > 0)
            {
                EditorGUILayout.HelpBox(_uncoveredMeshes + " static renderers contributing to GI have no collider, so rays pass through them. " +
                                        (Volume.AddTemporaryColliders
                                            ? "Temporary mesh colliders will be added while rays are cast and removed afterwards."
                                            : "Add colliders, or enable 'Add Temporary Colliders'."),
                    Volume.AddTemporaryColliders ? MessageType.Info : MessageType.Warning);
            }
            using (new EditorGUI.DisabledScope(Session.Sh == null))
            {
                if (GUILayout.Button("Extract features"))
                {
                    RunStep(PipelineStep.Features, (progress, cancel) => LpnnPipeline.ExtractFeatures(Volume, Session, progress, cancel));
                    _uncoveredMeshes = ColliderAudit.StaticMeshesWithoutColliders().Count;
                }
            }
            Status(Steps[PipelineStep.Features]);
        }

        private void ScoringSection()
        {
            Header("4. Scoring");
            Field(LpnnVolume.Fields.Model);
            Field(LpnnVolume.Fields.ModelCard);
            Field(LpnnVolume.Fields.Backend);
            Field(LpnnVolume.Fields.ScoringPointLimit);
            serializedObject.ApplyModifiedProperties();
            InferencePackageBox();
            foreach (var check in ModelChecks())
                EditorGUILayout.HelpBox(check.Message, check.Severity == CheckSeverity.Error ? MessageType.Error : MessageType.Warning);
            using (new EditorGUI.DisabledScope(Session.Features == null))
            {
                if (GUILayout.Button("Score evaluation points"))
                    RunStep(PipelineStep.Scoring, (progress, cancel) => LpnnPipeline.Score(Volume, Session));
            }
            Status(Steps[PipelineStep.Scoring]);
            var record = Volume.LastScores;
            if (!record.IsEmpty)
                EditorGUILayout.LabelField("Stored scores", InvariantFormat.Count(record.Count) + " points, " + record.Backend + ", model '" + record.Model + "'");
            if (!record.IsEmpty)
                EditorGUILayout.LabelField("Invalid points", record.Valid == null ? "unknown (scored before validity): run Features and Scoring again"
                    : InvariantFormat.Count(record.InvalidCount) + " inside geometry (never probes)");
        }

        private void PlacementSection()
        {
            Header("5. Placement");
            Field(LpnnVolume.Fields.TargetGroup);
            Field(LpnnVolume.Fields.Method);
            serializedObject.ApplyModifiedProperties();
            bool byScores = PlacementMethods.NeedsScores(Volume.Method);
            if (byScores)
                EditorGUILayout.HelpBox("The Network method was measured worse than Insertion at every budget from 5 % and at the tolerance " +
                                        "(Documentation~/benchmarks.md §7.1); it is faster (milliseconds).", MessageType.None);
            var policy = PolicyPopup();
            switch (policy)
            {
                case SelectionPolicy.Spread:
                case SelectionPolicy.Budget: Field(LpnnVolume.Fields.Budget); break;
                case SelectionPolicy.Threshold: Field(LpnnVolume.Fields.Threshold); break;
                case SelectionPolicy.Tolerance: Field(LpnnVolume.Fields.Tolerance); break;
                default: Field(LpnnVolume.Fields.Percentile); break;
            }
            Field(LpnnVolume.Fields.KeepBoundsCorners);
            serializedObject.ApplyModifiedProperties();
            var preview = PreviewCount();
            using (new EditorGUILayout.HorizontalScope())
            {
                using (new EditorGUI.DisabledScope(byScores ? Volume.LastScores.IsEmpty : Session.Sh == null))
                {
                    if (!byScores && KnownInsertionRanking() == null && GUILayout.Button("Rank by insertion"))
                        StepRunner.Run(Volume, Steps[PipelineStep.Placement], (progress, cancel) => RankByInsertion(progress, cancel));
                    if (policy == SelectionPolicy.Tolerance && GUILayout.Button("Find probes"))
                        StepRunner.Run(Volume, Steps[PipelineStep.Placement], (progress, cancel) => SearchTolerance(progress, cancel));
                    if (GUILayout.Button("Apply"))
                        RunStep(PipelineStep.Placement, (progress, cancel) =>
                            preview != null ? LpnnPipeline.Apply(Volume, Session, preview) : LpnnPipeline.Apply(Volume, Session, progress, cancel));
                }
                if (GUILayout.Button("Clear"))
                    StepRunner.Run(Volume, Steps[PipelineStep.Placement], (progress, cancel) => { ProbeGroupWriter.Clear(Volume.TargetGroup); return "probes cleared"; });
                if (GUILayout.Button("Import .probes.json…")) ImportProbes();
            }
            Status(Steps[PipelineStep.Placement]);
        }

        /// <summary>The policy in the order an artist should consider them (Spread first, the thesis' Percentile next), not
        /// the order of the enum, whose values are stored in scenes and only ever appended to.</summary>
        private SelectionPolicy PolicyPopup()
        {
            var property = serializedObject.FindProperty(LpnnVolume.Fields.Policy);
            // The enum is declared in value order, so its index is its value.
            var current = (SelectionPolicy)property.enumValueIndex;
            int shown = Math.Max(0, Array.IndexOf(PolicyOrder, current));
            // EditorGUILayout.Popup: UnityCsReference Editor/Mono/EditorGUILayout.cs
            int chosen = EditorGUILayout.Popup("Policy", shown, PolicyLabels);
            if (chosen != shown) property.enumValueIndex = (int)PolicyOrder[chosen];
            return PolicyOrder[chosen];
        }

        private static readonly SelectionPolicy[] PolicyOrder =
        {
            SelectionPolicy.Spread, SelectionPolicy.Percentile, SelectionPolicy.Budget, SelectionPolicy.Threshold, SelectionPolicy.Tolerance,
        };

        private static readonly string[] PolicyLabels = { "Spread", "Percentile (thesis)", "Top-K", "Threshold", "Tolerance (default)" };

        private void ExportSection()
        {
            Header("6. Capture export (retraining)");
            Field(LpnnVolume.Fields.GroundTruthGroup);
            using (new EditorGUILayout.HorizontalScope())
            {
                Field(LpnnVolume.Fields.DatasetFolder);
                if (GUILayout.Button("Choose…", GUILayout.Width(70)))
                {
                    string folder = EditorUtility.SaveFolderPanel("Dataset folder", LpnnPaths.DatasetFolderFor(Volume), "");
                    if (!string.IsNullOrEmpty(folder)) serializedObject.FindProperty(LpnnVolume.Fields.DatasetFolder).stringValue = folder;
                    EndGuiAfterModal();
                }
            }
            serializedObject.ApplyModifiedProperties();
            string datasetFolder = LpnnPaths.DatasetFolderFor(Volume);
            EditorGUILayout.LabelField("Dataset folder", datasetFolder, EditorStyles.wordWrappedMiniLabel);
            if (LpnnPaths.IsInsideAssets(datasetFolder))
                EditorGUILayout.HelpBox("This folder is inside Assets/: Unity will import every capture as an asset. A folder beside Assets " +
                                        "(the default <project>/LpnnDatasets) keeps datasets out of the project.", MessageType.Warning);
            using (new EditorGUI.DisabledScope(Session.Features == null))
            using (new EditorGUILayout.HorizontalScope())
            {
                if (GUILayout.Button("Save capture…"))
                {
                    Directory.CreateDirectory(datasetFolder);
                    string path = EditorUtility.SaveFilePanel("Save capture", datasetFolder, CaptureExport.DefaultStem(Volume), "lpnncap");
                    if (!string.IsNullOrEmpty(path))
                        StepRunner.Run(Volume, Steps.Export, (progress, cancel) =>
                        {
                            string written = CaptureExport.Save(Volume, Session, path, out string labels);
                            return "saved " + written + "; " + labels;
                        });
                    EndGuiAfterModal();
                }
                if (GUILayout.Button("Append to dataset"))
                {
                    StepRunner.Run(Volume, Steps.Export, (progress, cancel) =>
                    {
                        string written = CaptureExport.Append(Volume, Session, datasetFolder, CaptureExport.DefaultStem(Volume), out string labels);
                        return "appended " + written + "; " + labels;
                    });
                    EndGuiAfterModal();
                }
            }
            Status(Steps.Export);
        }

        // ------------------------------------------------------------------------------------------ helpers

        /// <summary>After a modal panel or a long step run from inside layout scopes, the IMGUI event has changed under the
        /// open groups; finishing the layout then fails with "EndLayoutGroup: BeginLayoutGroup must be called first". Unity's
        /// own inspectors end the GUI pass instead (UnityCsReference Modules/IMGUI/GUIUtility.cs ExitGUI, which throws
        /// ExitGUIException that Unity catches). Pending serialized edits are applied first so the choice is not lost.</summary>
        private void EndGuiAfterModal()
        {
            serializedObject.ApplyModifiedProperties();
            GUIUtility.ExitGUI();
        }

        private void RunAll()
        {
            if (!ConfirmHeavy("run every step")) return;
            if (EvaluationLighting.RewritesSceneLighting(Volume) && !ConfirmSceneBake()) return;
            LpnnPipeline.Run(Volume, Session, PipelineStep.Placement, volume => EvaluationLighting.Create(volume, true), RunStep);
        }

        /// <summary>Runs one pipeline step under a progress bar, shows its summary (and any caveat) as the step's ✓ line, and
        /// records which data that line describes.</summary>
        private bool RunStep(PipelineStep step, LpnnPipeline.StepWork work)
        {
            var state = Steps[step];
            StepResult result = null;
            if (!StepRunner.Run(Volume, state, (progress, cancel) => StepSummaries.Describe(result = work(progress, cancel)))) return false;
            Steps.Reported(step, Session, Volume);
            string warning = StepSummaries.Warning(result);
            state.Warn(warning);
            if (warning.Length > 0) Debug.LogWarning("[LPNN] " + Volume.name + " — " + state.Name + ": " + warning, Volume);
            return true;
        }

        private void ImportProbes()
        {
            string path = EditorUtility.OpenFilePanel("Import probe positions (*.probes.json)", LpnnPaths.DatasetFolderFor(Volume), "json");
            if (!string.IsNullOrEmpty(path))
                StepRunner.Run(Volume, Steps[PipelineStep.Placement], (progress, cancel) =>
                    ProbeGroupWriter.Import(Volume.TargetGroup, path) + " probes imported from " + Path.GetFileName(path));
            EndGuiAfterModal();
        }

        private void UpdatePointCount()
        {
            string signature;
            System.Collections.Generic.List<GridBox> boxes;
            try
            {
                boxes = Volume.GetWorldBoxes();
                signature = GridSignature.Of(boxes, Volume.CellSize) + "|" + Volume.PointLimit;
            }
            catch (LpnnException e)
            {
                _countText = e.Message;
                _countType = MessageType.Error;
                return;
            }
            if (signature == _countSignature) return;
            _countSignature = signature;
            try
            {
                _countedPoints = GridBuilder.CountPoints(boxes, Volume.CellSize, Volume.PointLimit);
                _countText = InvariantFormat.Count(_countedPoints) + " evaluation points; about " +
                             StepSummaries.Megabytes(EvaluationGrid.EstimateBytes(_countedPoints, FeatureExtractor.Schema.Count)) + " through the pipeline.";
                _countType = MessageType.Info;
                if (_countedPoints > Volume.PointLimit)
                {
                    _countText += " Over the point limit of " + InvariantFormat.Count(Volume.PointLimit) + ": use a larger cell size or smaller boxes.";
                    _countType = MessageType.Error;
                }
                else if (_countedPoints > LargeGridWarning)
                {
                    _countText += " That is a large grid: lighting and features will take a while (you will be asked before they run).";
                    _countType = MessageType.Warning;
                }
                if (Session.Grid != null && Session.GridSignature != GridSignature.Of(boxes, Volume.CellSize))
                    _countText += "\nThe volume changed since the grid was built: build it again.";
            }
            catch (LpnnException e)
            {
                _countedPoints = 0;
                _countText = e.Message;
                _countType = MessageType.Error;
            }
        }

        /// <summary>Shows how many probes Apply would place and their estimated error; returns the selection (null when
        /// there is none yet).</summary>
        private SelectionResult PreviewCount()
        {
            bool byScores = PlacementMethods.NeedsScores(Volume.Method);
            var record = Volume.LastScores;
            if (byScores && record.IsEmpty)
            {
                EditorGUILayout.HelpBox("No scores yet: run the Scoring step (or import a .probes.json).", MessageType.None);
                return null;
            }
            if (!byScores && Session.Sh == null)
            {
                EditorGUILayout.HelpBox("No lighting yet: the insertion method ranks points by the Lighting data step's SH (or import a .probes.json).",
                                        MessageType.None);
                return null;
            }
            string error;
            SelectionResult result;
            EvaluationGrid grid = null;
            try
            {
                grid = LpnnPipeline.PlacementGrid(Volume, Session);
                if (byScores)
                {
                    result = _preview.Get(grid, record, Volume.GetSelectionSettings(), out error);
                }
                else
                {
                    int[] ranking = KnownInsertionRanking();
                    if (ranking != null)
                    {
                        result = _preview.GetRanked(grid, ranking, PlacementInputs.ValidPoints(Session, grid), Volume.GetSelectionSettings(), out error);
                    }
                    else
                    {
                        result = null;
                        error = "The insertion method ranks the points once (about a second per 1,000 points): press 'Rank by insertion' " +
                                "(Apply and Find probes also rank first).";
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
            string count = "Apply would place " + InvariantFormat.Count(result.Indices.Length) + " of " +
                           InvariantFormat.Count(grid.Count) + " points" + StepSummaries.Extras(result) + "." +
                           (byScores ? ValidityLine(record) : InsertionValidityLine(PlacementInputs.ValidPoints(Session, grid)));
            EditorGUILayout.HelpBox(count + "\n" + ErrorReadout(result, grid, out MessageType type), type);
            if (!_estimate.Has(result, Session) && Session.Sh != null && !PlacementErrorEstimate.IsLive(grid) && GUILayout.Button("Estimate error"))
                _estimate.Get(result, Session, grid, out bool _);
            return result;
        }

        /// <summary>The insertion preview's line on invalid points: known only once the Features step ran on this grid.</summary>
        private static string InsertionValidityLine(bool[] valid)
        {
            if (valid == null)
                return "\nValidity unknown: run the Features step to exclude points inside geometry (its rays find them).";
            int invalid = ValidCandidates.CountInvalid(valid);
            return invalid == 0 ? "" : "\n" + InvariantFormat.Count(invalid) + " points inside geometry are never probes.";
        }

        /// <summary>The preview's line on invalid points (Documentation~/features.md "Probe validity").</summary>
        private static string ValidityLine(LpnnScoreRecord record)
        {
            if (record.Valid == null)
                return "\nValidity unknown (scored before validity existed): run Features and Scoring again to exclude points inside geometry.";
            int invalid = record.InvalidCount;
            return invalid == 0 ? "" : "\n" + InvariantFormat.Count(invalid) + " of " + InvariantFormat.Count(record.Count) +
                                       " points are inside geometry (more than a quarter of their rays hit back faces) and are never probes.";
        }

        /// <summary>The estimated error line under the probe count: live on small grids, on request on large ones.</summary>
        private string ErrorReadout(SelectionResult result, EvaluationGrid grid, out MessageType type)
        {
            type = MessageType.Info;
            if (Session.Sh == null || Session.Grid != grid)
                return "Estimated error: needs the lighting of this grid (run the Lighting data step).";
            if (!_estimate.Has(result, Session) && !PlacementErrorEstimate.IsLive(grid))
                return "Estimated error: press 'Estimate error' (" + InvariantFormat.Count(grid.Count) + " points is too many to follow every change).";
            string text = _estimate.Get(result, Session, grid, out bool failed);
            if (failed) type = MessageType.Warning;
            return text;
        }

        private string SearchTolerance(ProgressCallback progress, System.Threading.CancellationToken cancel)
        {
            var grid = LpnnPipeline.PlacementGrid(Volume, Session);
            var settings = Volume.GetSelectionSettings();
            var result = PlacementMethods.NeedsScores(Volume.Method)
                ? _preview.Search(grid, Volume.LastScores, settings, PlacementInputs.Evaluator(Session, grid))
                : _preview.SearchRanked(grid, PlacementInputs.RankByInsertion(Session, grid, progress, cancel), PlacementInputs.ValidPoints(Session, grid), settings, PlacementInputs.Evaluator(Session, grid));
            return InvariantFormat.Count(result.Indices.Length) + " probes are within the tolerance" + StepSummaries.Extras(result);
        }

        /// <summary>The insertion ranking of the current lighting if already computed (never computes during a repaint).</summary>
        private int[] KnownInsertionRanking()
        {
            try
            {
                return PlacementInputs.KnownInsertionRanking(Session, LpnnPipeline.FreshLitGrid(Volume, Session));
            }
            catch (LpnnException)
            {
                return null;
            }
        }

        private string RankByInsertion(ProgressCallback progress, System.Threading.CancellationToken cancel)
        {
            var grid = LpnnPipeline.FreshLitGrid(Volume, Session);
            PlacementInputs.RankByInsertion(Session, grid, progress, cancel);
            return InvariantFormat.Count(grid.Count) + " points ranked by insertion";
        }

        /// <summary>The inference-package decision of <see cref="InferencePackageCheck"/> when something must change.</summary>
        private static void InferencePackageBox()
        {
            var decision = InferencePackageCheck.Current;
            if (decision == null || decision.Action == InferencePackageAction.Ready) return;
            EditorGUILayout.HelpBox(decision.Message, MessageType.Error);
            using (new EditorGUI.DisabledScope(InferencePackageCheck.Busy))
            {
                if (GUILayout.Button(InferencePackageCheck.ApplyLabel(decision)))
                {
                    InferencePackageCheck.Apply();
                    // The Package Manager call ends in a domain reload: leave this IMGUI pass now (UnityCsReference
                    // Modules/IMGUI/GUIUtility.cs ExitGUI) instead of finishing layout groups on a reloading editor.
                    GUIUtility.ExitGUI();
                }
            }
        }

        /// <summary>Every problem of the model, its card and the inference package (LpnnScoring.Checks), re-checked when the
        /// Model or Card field changes.</summary>
        private IReadOnlyList<ModelCheck> ModelChecks()
        {
            if (Volume.ModelCard == _checkedCard && Volume.Model == _checkedModel && _checkedCard != null) return _modelChecks;
            _checkedCard = Volume.ModelCard;
            _checkedModel = Volume.Model;
            _modelChecks = LpnnScoring.Checks(Volume, FeatureExtractor.Schema, out ModelCard _);
            return _modelChecks;
        }

        private bool ConfirmHeavy(string what)
        {
            if (_countedPoints <= LargeGridWarning) return true;
            // EditorUtility.DisplayDialog: Editor/Mono/EditorUtility.bindings.cs
            return EditorUtility.DisplayDialog("LPNN Probes: large grid",
                "The grid has " + InvariantFormat.Count(_countedPoints) + " points (about " +
                StepSummaries.Megabytes(EvaluationGrid.EstimateBytes(_countedPoints, FeatureExtractor.Schema.Count)) +
                "). Do you want to " + what + " now? You can cancel from the progress bar.", "Continue", "Cancel");
        }

        private static bool ConfirmSceneBake()
        {
            return EditorUtility.DisplayDialog("LPNN Probes: bake the scene's lighting?",
                "Unity 2022.3 can only bake lighting at arbitrary points as part of a full bake. This will run Generate Lighting with the " +
                "scene's current Lighting Settings, replacing its lighting data (lightmaps, probes) with a fresh bake of those settings, " +
                "and read the evaluation points from it.\n\nIf your current lighting was baked with other settings, save a copy first, " +
                "or choose 'Interpolate Scene Probes', which writes nothing.", "Bake", "Cancel");
        }

        private SerializedProperty Field(string name)
        {
            var property = serializedObject.FindProperty(name);
            EditorGUILayout.PropertyField(property, true);
            return property;
        }

        private static void Header(string title)
        {
            EditorGUILayout.Space();
            EditorGUILayout.LabelField(title, EditorStyles.boldLabel);
        }

        private static void Status(StepState step)
        {
            if (step.Done)
                EditorGUILayout.LabelField("✓ " + step.Summary + Timing(step), EditorStyles.wordWrappedMiniLabel);
            if (step.Warning.Length > 0) EditorGUILayout.HelpBox(step.Warning, MessageType.Warning);
            if (step.Error.Length > 0) EditorGUILayout.HelpBox(step.Error + Timing(step), MessageType.Error);
        }

        private static string Timing(StepState step) =>
            step.Seconds < 0 ? "" : " (" + InvariantFormat.Number(Math.Round(step.Seconds, 2)) + " s)";
    }
}
