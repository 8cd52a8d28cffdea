using System;
using System.Linq;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Json;
using Lpnn.Probes.Core.Scoring;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    [TestFixture]
    public class ScoringTests
    {
        /// <summary>A card as `lpnn export` writes it, for the v1 schema, with one field replaced when asked.</summary>
        private static string Card(string key = null, JsonValue value = null)
        {
            var root = JsonValue.NewObject();
            root.Set("format", JsonValue.From("lpnn.modelcard"));
            root.Set("version", JsonValue.From(1));
            root.Set("model_file", JsonValue.From("lpnn_default.onnx"));
            root.Set("schema", JsonValue.From("lpnn.features.v1"));
            root.Set("feature_names", JsonValue.ArrayOf(FeatureSchema.LpnnV1.Names.Select(n => JsonValue.From(n))));
            root.Set("feature_count", JsonValue.From(FeatureSchema.LpnnV1.Count));
            var input = JsonValue.NewObject();
            input.Set("name", JsonValue.From("features"));
            root.Set("input", input);
            var output = JsonValue.NewObject();
            output.Set("name", JsonValue.From("importance"));
            root.Set("output", output);
            root.Set("opset", JsonValue.From(15));
            if (key != null) root.Set(key, value);
            return JsonWriter.Write(root, true);
        }

        [Test]
        public void MatchingCardPassesTheSchemaCheck()
        {
            var card = ModelCard.Parse(Card(), "lpnn_default.card.json");
            Assert.That(card.Schema, Is.EqualTo("lpnn.features.v1"));
            Assert.That(card.FeatureCount, Is.EqualTo(19));
            card.CheckFeatures(FeatureSchema.LpnnV1);
        }

        [Test]
        public void CardOfAnotherSchemaIsRefusedNamingBothSchemas()
        {
            var names = JsonValue.ArrayOf(FeatureSchema.Thesis30.Names.Select(n => JsonValue.From(n)));
            string text = Card("feature_names", names).Replace("\"feature_count\": 19", "\"feature_count\": 30")
                                                      .Replace("\"schema\": \"lpnn.features.v1\"", "\"schema\": \"lpnn.thesis30\"");
            var card = ModelCard.Parse(text, "old.card.json");
            var error = Assert.Throws<ModelCardException>(() => card.CheckFeatures(FeatureSchema.LpnnV1));
            StringAssert.Contains("'lpnn.features.v1' (19 features)", error.Message);
            StringAssert.Contains("expects schema 'lpnn.thesis30' (30 features)", error.Message);
        }

        [Test]
        public void RenamedFeatureIsRefusedNamingTheIndex()
        {
            var names = FeatureSchema.LpnnV1.Names.ToArray();
            names[4] = "light_var";
            var card = ModelCard.Parse(Card("feature_names", JsonValue.ArrayOf(names.Select(n => JsonValue.From(n)))), "x.card.json");
            var error = Assert.Throws<ModelCardException>(() => card.CheckFeatures(FeatureSchema.LpnnV1));
            StringAssert.Contains("feature 4 is 'light_variance' in the extractor and 'light_var' in the model", error.Message);
        }

        [TestCase("format", "\"something.else\"", "format 'something.else'")]
        [TestCase("feature_count", "18", "'feature_count' 18 differs from the 19 feature names")]
        [TestCase("schema", "3", "field 'schema' is missing or not a string")]
        [TestCase("input", "{\"name\": \"x\"}", "the graph's input/output are 'x'/'importance'")]
        public void MalformedCardsNameTheField(string key, string json, string expected)
        {
            var error = Assert.Throws<ModelCardException>(() => ModelCard.Parse(Card(key, JsonParser.Parse(json)), "bad.card.json"));
            StringAssert.Contains("bad.card.json: ", error.Message);
            StringAssert.Contains(expected, error.Message);
        }

        [Test]
        public void EveryFaultyFieldIsReportedAtOnce()
        {
            string text = Card("format", JsonValue.From("something.else"));
            text = text.Replace("\"schema\": \"lpnn.features.v1\"", "\"schema\": 3").Replace("\"name\": \"importance\"", "\"name\": \"scores\"");
            var card = ModelCard.Read(text, "bad.card.json", out var problems);
            Assert.That(card, Is.Null);
            var errors = problems.Where(p => p.Severity == CheckSeverity.Error).Select(p => p.Message).ToList();
            Assert.That(errors.Count, Is.EqualTo(3), string.Join("\n", errors));
            StringAssert.Contains("format 'something.else'", errors[0]);
            StringAssert.Contains("field 'schema' is missing or not a string", errors[1]);
            StringAssert.Contains("the graph's input/output are 'features'/'scores'", errors[2]);
            var thrown = Assert.Throws<ModelCardException>(() => ModelCard.Parse(text, "bad.card.json"));
            foreach (string error in errors) StringAssert.Contains(error, thrown.Message);
        }

        [Test]
        public void EveryRenamedFeatureIsReported()
        {
            var names = FeatureSchema.LpnnV1.Names.ToArray();
            names[4] = "light_var";
            names[7] = "renamed";
            var card = ModelCard.Parse(Card("feature_names", JsonValue.ArrayOf(names.Select(n => JsonValue.From(n)))), "x.card.json");
            var problems = card.FeatureChecks(FeatureSchema.LpnnV1);
            Assert.That(problems.Select(p => p.Severity), Is.EqualTo(new[] { CheckSeverity.Error, CheckSeverity.Error }));
            StringAssert.Contains("feature 4 is 'light_variance' in the extractor and 'light_var' in the model", problems[0].Message);
            StringAssert.Contains("feature 7 is '" + FeatureSchema.LpnnV1.Names[7] + "' in the extractor and 'renamed'", problems[1].Message);
            Assert.That(ModelCard.Parse(Card(), "ok.card.json").FeatureChecks(FeatureSchema.LpnnV1), Is.Empty);
        }

        [Test]
        public void MissingTrainingProvenanceIsAWarningThatDoesNotStopScoring()
        {
            var card = ModelCard.Read(Card(), "bare.card.json", out var problems);
            Assert.That(card, Is.Not.Null);
            Assert.That(problems.Select(p => p.Severity), Is.EqualTo(new[] { CheckSeverity.Warning }));
            StringAssert.Contains("no 'training' object", problems[0].Message);
            var training = JsonValue.NewObject();
            training.Set("seed", JsonValue.From(0));
            Assert.That(ModelCard.Read(Card("training", training), "full.card.json", out var none), Is.Not.Null);
            Assert.That(none, Is.Empty);
        }

        [Test]
        public void InvalidJsonNamesLineAndColumn()
        {
            var error = Assert.Throws<ModelCardException>(() => ModelCard.Parse("{\"format\": }", "broken.card.json"));
            StringAssert.Contains("broken.card.json: line 1, column 12", error.Message);
        }

        [Test]
        public void AutoTriesGpuThenCpuOnlyWhenComputeShadersExist()
        {
            Assert.That(ScoringPlan.Attempts(ScoringBackendPreference.Auto, true), Is.EqualTo(new[] { ScoringDevice.GpuCompute, ScoringDevice.Cpu }));
            Assert.That(ScoringPlan.Attempts(ScoringBackendPreference.Auto, false), Is.EqualTo(new[] { ScoringDevice.Cpu }));
            Assert.That(ScoringPlan.Attempts(ScoringBackendPreference.Cpu, true), Is.EqualTo(new[] { ScoringDevice.Cpu }));
            Assert.That(ScoringPlan.Attempts(ScoringBackendPreference.Gpu, true), Is.EqualTo(new[] { ScoringDevice.GpuCompute }));
            var error = Assert.Throws<ScoringException>(() => ScoringPlan.Attempts(ScoringBackendPreference.Gpu, false));
            StringAssert.Contains("choose Auto or CPU", error.Message);
        }

        [Test]
        public void InputShapeIsOneCloudOfPointsByFeatures()
        {
            Assert.That(ScoringPlan.InputShape(1234, 19, 0.5), Is.EqualTo(new[] { 1, 1234, 19 }));
        }

        [Test]
        public void PointGuardSuggestsACellSizeThatFits()
        {
            var error = Assert.Throws<ScoringException>(() => ScoringPlan.CheckPointCount(8000, 0.5, 1000));
            StringAssert.Contains("the grid has 8,000 evaluation points, but scoring runs on at most 1,000", error.Message);
            // 0.5 · ∛8 = 1: a grid of 1/8 the points per volume.
            StringAssert.Contains("use a cell size of about 1 or larger (now 0.5)", error.Message);
            Assert.Throws<ScoringException>(() => ScoringPlan.CheckPointCount(0, 0.5, 1000));
            ScoringPlan.CheckPointCount(1000, 0.5, 1000);
        }

        [Test]
        public void OutputMustHaveOneValuePerPoint()
        {
            Assert.That(ScoringPlan.CheckOutput(new float[3], 3, "m.onnx").Length, Is.EqualTo(3));
            var error = Assert.Throws<ScoringException>(() => ScoringPlan.CheckOutput(new float[6], 3, "m.onnx"));
            StringAssert.Contains("returned 6 values for 3 points", error.Message);
            Assert.Throws<ScoringException>(() => ScoringPlan.CheckOutput(null, 3, "m.onnx"));
        }
    }
}
