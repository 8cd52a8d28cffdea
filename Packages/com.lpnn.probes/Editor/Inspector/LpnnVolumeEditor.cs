using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Placement;
using Lpnn.Probes.Core.Scoring;
using UnityEditor;
using UnityEngine;

namespace Lpnn.Probes.Editor
{
    /// <summary>The LPNN volume inspector, in the order of the thesis' panel (§3.5): Volume, Lighting data, Features,
    /// Scoring, Placement (<see cref="PlacementPanel"/>), Capture export (<see cref="ExportPanel"/>). Settings are edited
    /// through SerializedProperty (Undo and prefab overrides for free: UnityCsReference Editor/Mono/SerializedObject.bindings.cs);
    /// each step shows its state, last duration and last error (<see cref="StepStates"/>). The work itself is in
    /// <see cref="LpnnPipeline"/>, the texts in <see cref="LpnnVolumeStyles"/>.</summary>
    [CustomEditor(typeof(LpnnVolume))]
    internal sealed class LpnnVolumeEditor : UnityEditor.Editor
    {
        private readonly LpnnBoxHandles _boxHandles = new LpnnBoxHandles();
        private readonly PointCountEstimate _pointCount = new PointCountEstimate();
        private readonly ModelCheckCache _modelChecks = new ModelCheckCache();
        private readonly PlacementPanel _placement = new PlacementPanel();
        private LpnnVolumeProperties _properties;
        private int _uncoveredMeshes = -1;
        /// <summary>Score overrides a 0.1.0 prefab instance left in the scene (counted once per inspector: reading every
        /// modification of a bloated instance on each repaint would be the cost this removes).</summary>
        private int _legacyScoreOverrides;

        private LpnnVolume Volume => (LpnnVolume)target;
        private LpnnSession Session => LpnnSession.For(Volume);
        private StepStates Steps => StepStates.For(Volume);

        private void OnEnable()
        {
            _properties = new LpnnVolumeProperties(serializedObject);
            _uncoveredMeshes = ColliderAudit.StaticMeshesWithoutColliders(Volume.gameObject.scene).Count;
            _legacyScoreOverrides = LegacyScoreOverrides.Count(Volume);
        }

        public override void OnInspectorGUI()
        {
            serializedObject.Update();
            Steps.DropStale(Session, Volume);
            EditorGUILayout.HelpBox(LpnnVolumeStyles.Introduction, MessageType.None);
            if (GUILayout.Button(LpnnVolumeStyles.RunAll))
            {
                RunAll();
                InspectorLayout.EndGuiAfterModal(serializedObject);  // after dialogs and progress bars, as ExportPanel does
            }
            VolumeSection();
            LightingSection();
            FeaturesSection();
            ScoringSection();
            _placement.Draw(Volume, Session, Steps, serializedObject, _properties, RunStep);
            ExportPanel.Draw(Volume, Session, Steps, serializedObject, _properties);
            serializedObject.ApplyModifiedProperties();
        }

        private void OnSceneGUI()
        {
            if (!Volume.ShowGizmos) return;
            // The serialized copy may be stale (an inspector edit, an Undo, a script): read it before the handles edit it, as
            // OnInspectorGUI does (UnityCsReference Editor/Mono/SerializedObject.bindings.cs Update).
            serializedObject.Update();
            _boxHandles.Draw(Volume, serializedObject, _properties.Boxes);
        }

        // ------------------------------------------------------------------------------------------ sections

        private void VolumeSection()
        {
            InspectorLayout.Header(LpnnVolumeStyles.VolumeHeader);
            InspectorLayout.Field(_properties.Boxes);
            InspectorLayout.Field(_properties.CellSize);
            InspectorLayout.Field(_properties.PointLimit);
            InspectorLayout.Field(_properties.ShowGizmos);
            InUseFields();
            serializedObject.ApplyModifiedProperties();
            _pointCount.Update(Volume, Session);
            EditorGUILayout.HelpBox(_pointCount.Text, _pointCount.Type);
            if (GUILayout.Button(LpnnVolumeStyles.BuildGrid))
            {
                if (LpnnDialogs.ConfirmHeavy(_pointCount.Points, "build the grid", HeavyOperation.Grid))
                    RunStep(PipelineStep.Grid, (progress, cancel) => LpnnPipeline.BuildGrid(Volume, Session, progress, cancel));
                InspectorLayout.EndGuiAfterModal(serializedObject);
            }
            InspectorLayout.Status(Steps[PipelineStep.Grid]);
            if (Session.InUse != null && Steps[PipelineStep.Grid].Done)
                EditorGUILayout.HelpBox(Session.InUse.Describe(), Session.InUse.Known ? MessageType.Info : MessageType.Warning);
        }

        /// <summary>The in-use rule's settings (Documentation~/in-use.md); the seeds and step height only where the rule reads them.</summary>
        private void InUseFields()
        {
            InspectorLayout.Field(_properties.InUseRule);
            InspectorLayout.Field(_properties.InUseBandHeight);
            InspectorLayout.Field(_properties.InUseSlopeLimit);
            // The edited value (applied to the volume at the end of the section): the enum is declared in value order, so its
            // index is its value (UnityCsReference Editor/Mono/SerializedProperty.bindings.cs enumValueIndex; arraySize below, same file).
            var rule = (Core.InUse.InUseRule)_properties.InUseRule.enumValueIndex;
            if (rule != Core.InUse.InUseRule.Band)
            {
                InspectorLayout.Field(_properties.InUseStepHeight);
                InspectorLayout.Field(_properties.InUseSeeds);
            }
            InspectorLayout.Field(_properties.UseNavMesh);
            if (rule == Core.InUse.InUseRule.Reachable && _properties.InUseSeeds.arraySize == 0)
                EditorGUILayout.HelpBox(LpnnVolumeStyles.ReachableNeedsSeeds, MessageType.Warning);
        }

        private void LightingSection()
        {
            InspectorLayout.Header(LpnnVolumeStyles.LightingHeader);
            InspectorLayout.Field(_properties.LightingSource);
            serializedObject.ApplyModifiedProperties();
            EditorGUILayout.HelpBox(EvaluationLighting.Explain(Volume), MessageType.Info);
            using (new EditorGUI.DisabledScope(Session.Grid == null))
            {
                if (GUILayout.Button(LpnnVolumeStyles.SampleLighting))
                {
                    bool bake = LpnnDialogs.ConfirmHeavy(_pointCount.Points, "sample the lighting", HeavyOperation.Lighting) &&
                                (!EvaluationLighting.RewritesSceneLighting(Volume) || LpnnDialogs.ConfirmSceneBake());
                    if (bake) RunStep(PipelineStep.Lighting, (progress, cancel) => LpnnPipeline.SampleLighting(Volume, Session, true, progress, cancel));
                    InspectorLayout.EndGuiAfterModal(serializedObject);
                }
            }
            InspectorLayout.Status(Steps[PipelineStep.Lighting]);
        }

        private void FeaturesSection()
        {
            InspectorLayout.Header(LpnnVolumeStyles.FeaturesHeader);
            InspectorLayout.Field(_properties.AddTemporaryColliders);
            serializedObject.ApplyModifiedProperties();
            if (_uncoveredMeshes > 0)
            {
                EditorGUILayout.HelpBox(_uncoveredMeshes + " static renderers contributing to GI have no collider, so rays pass through them. " +
                                        (Volume.AddTemporaryColliders ? LpnnVolumeStyles.CollidersAdded : LpnnVolumeStyles.CollidersMissing),
                    Volume.AddTemporaryColliders ? MessageType.Info : MessageType.Warning);
            }
            using (new EditorGUI.DisabledScope(Session.Sh == null))
            {
                if (GUILayout.Button(LpnnVolumeStyles.ExtractFeatures))
                {
                    RunStep(PipelineStep.Features, (progress, cancel) => LpnnPipeline.ExtractFeatures(Volume, Session, progress, cancel));
                    _uncoveredMeshes = ColliderAudit.StaticMeshesWithoutColliders(Volume.gameObject.scene).Count;
                    InspectorLayout.EndGuiAfterModal(serializedObject);
                }
            }
            InspectorLayout.Status(Steps[PipelineStep.Features]);
        }

        private void ScoringSection()
        {
            InspectorLayout.Header(LpnnVolumeStyles.ScoringHeader);
            InspectorLayout.Field(_properties.Model);
            InspectorLayout.Field(_properties.ModelCard);
            InspectorLayout.Field(_properties.Backend);
            InspectorLayout.Field(_properties.ScoringPointLimit);
            serializedObject.ApplyModifiedProperties();
            InferencePackageBox();
            foreach (var check in _modelChecks.For(Volume))
                EditorGUILayout.HelpBox(check.Message, check.Severity == CheckSeverity.Error ? MessageType.Error : MessageType.Warning);
            using (new EditorGUI.DisabledScope(Session.Features == null))
            {
                if (GUILayout.Button(LpnnVolumeStyles.ScorePoints))
                {
                    RunStep(PipelineStep.Scoring, (progress, cancel) => LpnnPipeline.Score(Volume, Session));
                    InspectorLayout.EndGuiAfterModal(serializedObject);
                }
            }
            InspectorLayout.Status(Steps[PipelineStep.Scoring]);
            LegacyScoreOverridesBox();
            var record = LpnnScores.For(Volume);
            if (record.IsEmpty) return;
            EditorGUILayout.LabelField(LpnnVolumeStyles.StoredScores, InvariantFormat.Count(record.Count) + " points, " + record.Backend + ", model '" + record.Model + "'");
            EditorGUILayout.LabelField(LpnnVolumeStyles.InvalidPoints, record.Valid == null ? LpnnVolumeStyles.ValidityUnknownSinceScoring
                : InvariantFormat.Count(record.InvalidCount) + " inside geometry (never probes)");
        }

        /// <summary>A prefab instance saved by 0.1.0 carries its scores as prefab overrides of a field that no longer exists
        /// (LegacyScoreOverrides): say so and offer to remove just those (one Undo step).</summary>
        private void LegacyScoreOverridesBox()
        {
            if (_legacyScoreOverrides == 0) return;
            EditorGUILayout.HelpBox(InvariantFormat.Count(_legacyScoreOverrides) + LpnnVolumeStyles.LegacyScoreOverrides, MessageType.Info);
            if (!GUILayout.Button(LpnnVolumeStyles.RemoveLegacyScoreOverrides)) return;
            int removed = LegacyScoreOverrides.Remove(Volume);
            _legacyScoreOverrides = LegacyScoreOverrides.Count(Volume);
            Debug.Log("[LPNN] removed " + removed + " old score overrides from '" + Volume.name + "' (save the scene to keep the change)");
        }

        // ------------------------------------------------------------------------------------------ running steps

        private void RunAll()
        {
            if (!LpnnDialogs.ConfirmHeavy(_pointCount.Points, "run every step", HeavyOperations.RunAll(Volume))) return;
            if (EvaluationLighting.RewritesSceneLighting(Volume) && !LpnnDialogs.ConfirmSceneBake()) return;
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
            // After Apply: the leaking points of the placed probes (Documentation~/leaks.md "What is reported"), own progress and cancel.
            var placed = result as PlacementResult;
            if (placed != null && placed.Selection != null && Session.Sh != null)
                LeaksAtPointsInUse.Run(Volume, Session, LpnnPipeline.PlacementGrid(Volume, Session), placed.Selection.Indices);
            string warning = StepSummaries.Warning(result);
            state.Warn(warning);
            if (warning.Length > 0) Debug.LogWarning("[LPNN] " + Volume.name + " — " + state.Name + ": " + warning, Volume);
            return true;
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
    }
}
