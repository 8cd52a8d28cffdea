using System;
using System.Collections.Generic;
using System.IO;
using Lpnn.Probes.Core;
using Lpnn.Probes.Core.Batch;
using Lpnn.Probes.Core.Json;
using Lpnn.Probes.Core.Placement;
using Lpnn.Probes.Core.Selection;
using UnityEditor;
using UnityEditor.SceneManagement;
using UnityEngine;
using Object = UnityEngine.Object;

namespace Lpnn.Probes.Editor
{
    /// <summary>Batch-mode entry point: <c>Unity -batchmode -projectPath P -executeMethod Lpnn.Probes.Editor.LpnnBatch.Run
    /// -lpnnScene Assets/…/Scene.unity [-lpnnMode place|export] [-lpnnOut folder] [-lpnnBake] …</c>
    /// (arguments: Core.Batch.BatchOptions, Documentation~/ci.md). Runs the pipeline on every LPNN volume of the scene,
    /// logs per volume what the inspector reports (in place mode also the pinned probes and the leak line, Core.Batch.BatchPlacementReport)
    /// and exits with EditorApplication.Exit (Editor/Mono/EditorApplication.bindings.cs): 0 when every volume succeeded,
    /// 1 when a volume failed, 2 when the arguments or the scene are unusable.</summary>
    public static class LpnnBatch
    {
        public const int ExitOk = 0;
        public const int ExitVolumeFailed = 1;
        public const int ExitBadInput = 2;

        public static void Run()
        {
            int code;
            try
            {
                code = Execute(Environment.GetCommandLineArgs());
            }
            catch (LpnnException e)
            {
                Debug.LogError("[LPNN batch] " + e.Message);
                code = ExitBadInput;
            }
            catch (Exception e)
            {
                Debug.LogException(e);
                code = ExitBadInput;
            }
            EditorApplication.Exit(code);
        }

        /// <summary>The whole run without exiting (tests call this); returns the exit code.</summary>
        public static int Execute(IReadOnlyList<string> commandLine)
        {
            var options = BatchOptions.Parse(commandLine);
            string scenePath = options.ScenePath.Replace('\\', '/');
            if (!File.Exists(Path.Combine(LpnnPaths.ProjectRoot, scenePath)))
                throw new LpnnException("-lpnnScene '" + scenePath + "' does not exist in the project " + LpnnPaths.ProjectRoot +
                                        " (give the path from the project folder, e.g. Assets/Scenes/Level.unity)");
            // EditorSceneManager.OpenScene: Editor/Mono/SceneManagement/EditorSceneManager.cs
            var scene = EditorSceneManager.OpenScene(scenePath, OpenSceneMode.Single);
            var volumes = new List<LpnnVolume>();
            foreach (var volume in SceneObjects.FindAll<LpnnVolume>())
                if (options.VolumeName == null || volume.name == options.VolumeName) volumes.Add(volume);
            if (volumes.Count == 0)
                throw new LpnnException("scene " + scenePath + " has no LPNN volume" + (options.VolumeName == null ? "" : " named '" + options.VolumeName + "'") +
                                        "; add one with GameObject > Light > LPNN Probes");
            volumes.Sort((a, b) => string.CompareOrdinal(a.name, b.name));
            LightProbeGroup truth = FindGroundTruth(options.LabelsGroupName);
            string folder = options.OutputFolder ??
                            Path.Combine(LpnnPaths.ProjectRoot, options.Mode == BatchMode.Export ? "LpnnDatasets" : "LpnnResults");
            Directory.CreateDirectory(folder);

            int failed = 0;
            foreach (var volume in volumes)
            {
                try
                {
                    Debug.Log("[LPNN batch] " + volume.name + ": " + RunVolume(volume, options, truth, folder));
                }
                catch (LpnnException e)
                {
                    failed++;
                    Debug.LogError("[LPNN batch] " + volume.name + ": " + e.Message);
                }
                catch (Exception e)
                {
                    failed++;
                    Debug.LogError("[LPNN batch] " + volume.name + ": unexpected " + e.GetType().Name + " (stack trace follows)");
                    Debug.LogException(e);
                }
            }
            if (options.SaveScene && options.Mode == BatchMode.Place) EditorSceneManager.SaveScene(scene);
            Debug.Log("[LPNN batch] " + (volumes.Count - failed) + " of " + volumes.Count + " volumes done; results in " + folder);
            return failed == 0 ? ExitOk : ExitVolumeFailed;
        }

        private static string RunVolume(LpnnVolume volume, BatchOptions options, LightProbeGroup truth, string folder)
        {
            // The command line chooses lighting source, backend and ground truth for this run only: the volume's saved choices
            // are restored afterwards, so -lpnnSaveScene never writes them over the artist's settings.
            var savedLighting = volume.Lighting;
            var savedBackend = volume.Backend;
            var savedTruth = volume.GroundTruthGroup;
            var savedMethod = volume.Method;
            try
            {
                // Without -lpnnBake nothing is baked: the scene's existing probes are interpolated.
                volume.SetLighting(options.Bake ? LightingSource.BakeAtEvaluationPoints : LightingSource.InterpolateSceneProbes);
                volume.SetBackend(options.Backend);
                if (truth != null) volume.SetGroundTruth(truth);
                if (options.Method.HasValue) volume.SetMethod(options.Method.Value);
                return RunVolumeSteps(volume, options, folder);
            }
            finally
            {
                volume.SetLighting(savedLighting);
                volume.SetBackend(savedBackend);
                volume.SetGroundTruth(savedTruth);
                volume.SetMethod(savedMethod);
            }
        }

        private static string RunVolumeSteps(LpnnVolume volume, BatchOptions options, string folder)
        {
            var session = LpnnSession.For(volume);
            var log = new List<string>();
            // Export mode stops after the features (a capture needs no scores); place mode runs what the volume's method
            // needs (LpnnPipeline.Run: scores for Network and Guided insertion only), then writes the positions file itself (the volume may have
            // no target group to apply to).
            bool export = options.Mode == BatchMode.Export;
            System.Numerics.Vector3[] positions;
            SelectionResult selection;
            BatchPlacementReport report;
            string stem = CaptureExport.DefaultStem(volume);
            using (var progress = new EditorProgressScope("LPNN batch " + volume.name))
            {
                LpnnPipeline.Run(volume, session, export ? PipelineStep.Features : PipelineStep.Scoring, v => EvaluationLighting.Create(v, options.Bake),
                    (step, work) =>
                    {
                        var result = work(progress.Callback, progress.Token);
                        log.Add(StepSummaries.Describe(result));
                        string warning = StepSummaries.Warning(result);
                        if (warning.Length > 0) Debug.LogWarning("[LPNN batch] " + volume.name + ": " + warning);
                        return true;
                    });
                if (export)
                {
                    log.Add("capture " + CaptureExport.Append(volume, session, folder, stem, out string labels) + " (" + labels + ")");
                    return string.Join("; ", log);
                }
                positions = LpnnPipeline.SelectedPositions(volume, session, progress.Callback, progress.Token, out selection);
                report = PlacementReport(volume, session, selection, progress);
            }
            // The positions file is the batch result; the group is filled too when the volume has one.
            if (volume.TargetGroup != null) ProbeGroupWriter.Apply(volume.TargetGroup, positions, "Place LPNN probes");
            var source = JsonValue.NewObject();
            source.Set("scene", JsonValue.From(volume.gameObject.scene.path));
            source.Set("volume", JsonValue.From(volume.name));
            source.Set("method", JsonValue.From(BatchOptions.MethodName(volume.Method)));
            if (PlacementMethods.NeedsScores(volume.Method))
            {
                source.Set("backend", JsonValue.From(LpnnScores.For(volume).Backend));
                source.Set("model", JsonValue.From(LpnnScores.For(volume).Model));
            }
            report.AddTo(source);
            string path = Path.Combine(folder, stem + ProbePositionsFile.Extension);
            ProbePositionsFile.Save(path, positions, source);
            // The inspector's ✓ line after Apply: the count, the error at the points in use, then its leak line.
            var error = LpnnPipeline.ErrorAtPointsInUseOf(session, LpnnPipeline.PlacementGrid(volume, session), selection, out string errorUnknown);
            log.Add(positions.Length + " probes" + StepSummaries.Extras(selection) + "; " + (error != null ? error.Describe() : errorUnknown) + "; " +
                    report.Describe() + " → " + path);
            return string.Join("; ", log);
        }

        /// <summary>What the inspector reports after Apply, for the batch log and the probes file (Core.Batch.BatchPlacementReport):
        /// the pinned probes among the placed ones and the leak report of the placed probes (Documentation~/leaks.md "What is
        /// reported": Unity's tetrahedralisation and physics rays, as LeaksAtPointsInUse computes it for the inspector). A
        /// leak report that cannot be made says why and does not fail the volume: its probes are placed either way.</summary>
        private static BatchPlacementReport PlacementReport(LpnnVolume volume, LpnnSession session, SelectionResult selection, EditorProgressScope progress)
        {
            var grid = LpnnPipeline.PlacementGrid(volume, session);
            var pins = LpnnPipeline.PinsOf(volume, session, grid);
            int pinned = pins == null ? 0 : pins.Count;
            try
            {
                var leaks = LeaksAtPointsInUse.Compute(volume, session, grid, selection.Indices, progress.Callback, progress.Token);
                return BatchPlacementReport.Of(pinned, leaks, LeaksAtPointsInUse.CountedNote(session.InUse));
            }
            catch (LpnnException e)
            {
                return BatchPlacementReport.WithoutLeaks(pinned, e.Message);
            }
            catch (Exception e) when (!(e is OperationCanceledException))
            {
                Debug.LogException(e);
                return BatchPlacementReport.WithoutLeaks(pinned, "unexpected " + e.GetType().Name + " (" + e.Message + "); the log has the stack trace");
            }
        }

        private static LightProbeGroup FindGroundTruth(string name)
        {
            if (name == null) return null;
            var holder = GameObject.Find(name);
            var group = holder != null ? holder.GetComponent<LightProbeGroup>() : null;
            if (group == null)
                throw new LpnnException("-lpnnLabels '" + name + "': no active GameObject with that name holds a LightProbeGroup");
            return group;
        }
    }
}
