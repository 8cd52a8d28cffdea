using System;
using System.Collections.Generic;
using Lpnn.Probes.Core;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Scoring;
using UnityEditor;
using UnityEngine;
#if LPNN_INFERENCE_ENGINE
using Unity.InferenceEngine;
#elif LPNN_SENTIS
using Unity.Sentis;
#endif

namespace Lpnn.Probes.Editor
{
    /// <summary>The scores of one run and the backend that produced them.</summary>
    public sealed class ScoreOutcome
    {
        public float[] Scores { get; }
        public ScoringDevice Device { get; }
        /// <summary>Why an earlier backend was abandoned (empty when the first one worked).</summary>
        public string Fallback { get; }

        public ScoreOutcome(float[] scores, ScoringDevice device, string fallback)
        {
            Scores = scores;
            Device = device;
            Fallback = fallback ?? "";
        }

        public string DeviceName => Device == ScoringDevice.GpuCompute ? "GPUCompute" : "CPU";
    }

    /// <summary>Scores features with the volume's model: checks the card against the extractor's schema and the point
    /// count before anything runs, then tries the backends the core's ScoringPlan lists (Auto: GPU compute when
    /// SystemInfo.supportsComputeShaders, otherwise CPU; CPU again if the GPU run throws).</summary>
    internal static class LpnnScoring
    {
        public const string PackageHint =
            "install com.unity.sentis 2.1.3 (Unity 2022.3) or com.unity.ai.inference 2.4.0 (Unity 6), never both, with the Package " +
            "Manager (the LPNN volume inspector offers it)";

        /// <summary>Parses the volume's card and checks it against the schema; throws one error listing everything to fix.</summary>
        public static ModelCard CheckCard(LpnnVolume volume, FeatureSchema schema)
        {
            var problems = CardChecks(volume, schema, out var card);
            ModelCheck.ThrowIfAnyError(problems);
            return card;
        }

        /// <summary>Every problem with the volume's card (errors and warnings); the card is null on any error.</summary>
        private static List<ModelCheck> CardChecks(LpnnVolume volume, FeatureSchema schema, out ModelCard card)
        {
            var problems = new List<ModelCheck>();
            card = null;
            var cardAsset = volume.ModelCard;
            if (cardAsset == null)
            {
                problems.Add(ModelCheck.Error("the volume has no model card; assign the .card.json beside the model (the shipped one is " +
                                              LpnnPaths.ShippedModelCard + ")"));
                return problems;
            }
            string source = AssetDatabase.GetAssetPath(cardAsset);
            card = ModelCard.Read(cardAsset.text, string.IsNullOrEmpty(source) ? cardAsset.name : source, out var cardProblems);
            problems.AddRange(cardProblems);
            if (card != null) problems.AddRange(card.FeatureChecks(schema));
            if (ModelCheck.AnyError(problems)) card = null;
            return problems;
        }

        /// <summary>Every problem with the volume's model, card and inference package, errors and warnings, without
        /// loading the model (cheap enough for the inspector, which shows them all). The card is null on any card error.</summary>
        public static IReadOnlyList<ModelCheck> Checks(LpnnVolume volume, FeatureSchema schema, out ModelCard card)
        {
            var problems = CardChecks(volume, schema, out card);
            string modelProblem = ModelProblem(volume.Model);
            if (modelProblem != null) problems.Add(ModelCheck.Error(modelProblem));
            else if (card != null && card.ModelFile != volume.Model.name + ".onnx")
                problems.Add(ModelCheck.Warning("the card describes '" + card.ModelFile + "' but the model is '" + volume.Model.name +
                                                "': assign the card written beside this model, or its inputs may be checked against another model's"));
            return problems;
        }

        /// <summary>Why the Model field cannot run (null when it can, as far as is known without loading it).</summary>
        private static string ModelProblem(UnityEngine.Object model)
        {
#if LPNN_INFERENCE_ENGINE || LPNN_SENTIS
            if (model == null) return "the volume has no model; assign an imported .onnx model (the shipped one is " + LpnnPaths.ShippedModel + ")";
            if (!(model is ModelAsset))
                return "the Model field holds a " + model.GetType().Name + " ('" + model.name + "'), not an imported ONNX model";
            return null;
#else
            return "no neural-network inference package is installed, so the model cannot run; " + PackageHint;
#endif
        }

        public static ScoreOutcome Score(LpnnVolume volume, LpnnSession session, FeatureSet features, double cellSize)
        {
            if (features == null) throw new LpnnException("there are no features to score; run the Features step first");
            var card = CheckCard(volume, features.Schema);
            int[] shape = ScoringPlan.InputShape(features.PointCount, features.Schema.Count, cellSize, volume.ScoringPointLimit);
            // SystemInfo.supportsComputeShaders: UnityCsReference Runtime/Export/SystemInfo/SystemInfo.bindings.cs (false with -nographics).
            var attempts = ScoringPlan.Attempts(volume.Backend, SystemInfo.supportsComputeShaders);
            return Run(volume, session, features, card, shape, attempts);
        }

        private static ScoreOutcome Run(LpnnVolume volume, LpnnSession session, FeatureSet features, ModelCard card, int[] shape,
            IReadOnlyList<ScoringDevice> attempts)
        {
#if LPNN_INFERENCE_ENGINE || LPNN_SENTIS
            string modelProblem = ModelProblem(volume.Model);
            if (modelProblem != null) throw new ScoringException(modelProblem);
            var asset = (ModelAsset)volume.Model;
            var runner = session.ModelRunner as InferenceBackendRunner;
            if (runner == null || !runner.Serves(asset))
            {
                session.ModelRunner?.Dispose();
                runner = new InferenceBackendRunner(asset);
                session.ModelRunner = runner;
            }
            runner.CheckGraph(card.ModelFile);
            var failures = new List<string>();
            for (int a = 0; a < attempts.Count; a++)
            {
                try
                {
                    float[] scores = runner.Run(features.Values, shape, attempts[a]);
                    return new ScoreOutcome(ScoringPlan.CheckOutput(scores, features.PointCount, card.ModelFile), attempts[a], string.Join("; ", failures));
                }
                catch (Exception e) when (a + 1 < attempts.Count && !(e is LpnnException))
                {
                    // A GPU that cannot run the graph: drop its worker and try the next backend.
                    runner.DisposeWorker();
                    failures.Add(attempts[a] + " failed (" + e.GetType().Name + ": " + e.Message + ")");
                    Debug.LogWarning("[LPNN] " + volume.name + ": scoring on " + attempts[a] + " failed, retrying on " + attempts[a + 1] + ": " + e.Message, volume);
                }
            }
            throw new InvalidOperationException("no scoring backend was tried");
#else
            throw new ScoringException(ModelProblem(volume.Model));
#endif
        }
    }
}
