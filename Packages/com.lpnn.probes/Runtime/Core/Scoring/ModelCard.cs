using System.Collections.Generic;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Json;
using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Core.Scoring
{
    /// <summary>The fields of a model card (<c>&lt;model&gt;.card.json</c>, Documentation~/model-contract.md) that decide
    /// whether a model can score a feature set. The rest of the card is provenance and is not interpreted here.</summary>
    public sealed class ModelCard
    {
        public const string FormatName = "lpnn.modelcard";
        public const int FormatVersion = 1;
        /// <summary>Graph input and output names fixed by the model contract.</summary>
        public const string ContractInputName = "features";
        public const string ContractOutputName = "importance";

        /// <summary>Where the card came from (file or asset name), for messages.</summary>
        public string Source { get; }
        public string ModelFile { get; }
        public string Schema { get; }
        public IReadOnlyList<string> FeatureNames { get; }
        public int FeatureCount => FeatureNames.Count;
        public string InputName { get; }
        public string OutputName { get; }

        private ModelCard(string source, string modelFile, string schema, string[] featureNames, string inputName, string outputName)
        {
            Source = source;
            ModelFile = modelFile;
            Schema = schema;
            FeatureNames = featureNames;
            InputName = inputName;
            OutputName = outputName;
        }

        /// <summary>Parses and checks a card's own consistency; throws one <see cref="ModelCardException"/> naming the card,
        /// every faulty field and what to do.</summary>
        public static ModelCard Parse(string json, string source)
        {
            var card = Read(json, source, out var problems);
            ModelCheck.ThrowIfAnyError(problems);
            return card;
        }

        /// <summary>Parses a card and returns every problem found (errors and warnings) instead of stopping at the first;
        /// the card is null when any problem is an error.</summary>
        public static ModelCard Read(string json, string source, out IReadOnlyList<ModelCheck> problems)
        {
            source = string.IsNullOrEmpty(source) ? "model card" : source;
            var reader = new CardReader(source);
            problems = reader.Problems;
            JsonValue root;
            try
            {
                root = JsonParser.Parse(json ?? "");
            }
            catch (JsonParseException e)
            {
                reader.Fail(e.Message);
                return null;
            }
            if (root.Kind != JsonKind.Object)
            {
                reader.Fail("the card must be a JSON object");
                return null;
            }
            string format = reader.String(root, "format");
            double? version = reader.WholeNumber(root, "version");
            if (format != null && version.HasValue && (format != FormatName || version.Value != FormatVersion))
                reader.Fail("format '" + format + "' version " + InvariantFormat.Number(version.Value) + " is not '" + FormatName + "' version " +
                            FormatVersion);
            string modelFile = reader.String(root, "model_file");
            string schema = reader.String(root, "schema");
            var names = reader.Names(root);
            double? count = reader.WholeNumber(root, "feature_count");
            if (names != null && count.HasValue && count.Value != names.Length)
                reader.Fail("'feature_count' " + InvariantFormat.Number(count.Value) + " differs from the " + names.Length + " feature names");
            var inputObject = reader.Object(root, "input");
            var outputObject = reader.Object(root, "output");
            string input = inputObject == null ? null : reader.String(inputObject, "name", "input.name");
            string output = outputObject == null ? null : reader.String(outputObject, "name", "output.name");
            if (input != null && output != null && (input != ContractInputName || output != ContractOutputName))
                reader.Fail("the graph's input/output are '" + input + "'/'" + output + "', but the model contract requires '" +
                            ContractInputName + "'/'" + ContractOutputName + "'");
            if (!root.TryGet("training", out var training) || training.Kind != JsonKind.Object)
                reader.Warn("the card does not say how the model was trained (no 'training' object): its data and held-out results are unknown");
            return ModelCheck.AnyError(reader.Problems)
                ? null
                : new ModelCard(source, modelFile, schema, names, input, output);
        }

        /// <summary>Stops scoring unless the features are exactly what the model reads (schema id, count and names, in
        /// order); the error names both schemas and every differing feature (the same rule as the trainer's check).</summary>
        public void CheckFeatures(FeatureSchema schema) => ModelCheck.ThrowIfAnyError(FeatureChecks(schema));

        /// <summary>Every difference between the features and what the model reads, as errors (none: the model can score them).</summary>
        public IReadOnlyList<ModelCheck> FeatureChecks(FeatureSchema schema)
        {
            if (schema == null) throw new System.ArgumentNullException(nameof(schema));
            var problems = new List<ModelCheck>();
            if (schema.Id != Schema || schema.Count != FeatureCount)
            {
                problems.Add(ModelCheck.Error(
                    "the features have schema '" + schema.Id + "' (" + schema.Count + " features) but the model '" + ModelFile + "' (card " +
                    Source + ") expects schema '" + Schema + "' (" + FeatureCount + " features); use a model trained on '" + schema.Id +
                    "' (e.g. the shipped lpnn_default) or retrain with `lpnn train` on captures of '" + schema.Id + "'"));
                return problems;
            }
            for (int f = 0; f < FeatureCount; f++)
            {
                if (FeatureNames[f] == schema.Names[f]) continue;
                problems.Add(ModelCheck.Error(
                    "the features and the model '" + ModelFile + "' (card " + Source + ") both use schema '" + Schema + "', but feature " + f +
                    " is '" + schema.Names[f] + "' in the extractor and '" + FeatureNames[f] + "' in the model; the card does not belong to this " +
                    "package version: re-export the model or update the package"));
            }
            return problems;
        }

        /// <summary>Reads a card's fields, recording a problem for each one missing or malformed instead of stopping.</summary>
        private sealed class CardReader
        {
            private readonly string _source;
            public readonly List<ModelCheck> Problems = new List<ModelCheck>();

            public CardReader(string source) { _source = source; }

            public void Fail(string what) =>
                Problems.Add(ModelCheck.Error(_source + ": " + what + "; assign the .card.json written beside the model by `lpnn export`"));

            public void Warn(string what) => Problems.Add(ModelCheck.Warning(_source + ": " + what));

            public string String(JsonValue obj, string key, string label = null)
            {
                if (obj.TryGet(key, out var value) && value.Kind == JsonKind.String) return value.AsString;
                Fail("field '" + (label ?? key) + "' is missing or not a string");
                return null;
            }

            public double? WholeNumber(JsonValue obj, string key)
            {
                if (obj.TryGet(key, out var value) && value.IsInteger) return value.AsNumber;
                Fail("field '" + key + "' is missing or not a whole number");
                return null;
            }

            public JsonValue Object(JsonValue obj, string key)
            {
                if (obj.TryGet(key, out var value) && value.Kind == JsonKind.Object) return value;
                Fail("field '" + key + "' is missing or not an object");
                return null;
            }

            public string[] Names(JsonValue root)
            {
                if (!root.TryGet("feature_names", out var value) || value.Kind != JsonKind.Array || value.Items.Count == 0)
                {
                    Fail("field 'feature_names' is missing, empty or not a list");
                    return null;
                }
                var names = new string[value.Items.Count];
                bool complete = true;
                for (int f = 0; f < names.Length; f++)
                {
                    var item = value.Items[f];
                    if (item.Kind == JsonKind.String && item.AsString.Length > 0)
                    {
                        names[f] = item.AsString;
                        continue;
                    }
                    Fail("feature_names[" + f + "] is not a non-empty string");
                    complete = false;
                }
                return complete ? names : null;
            }
        }
    }
}
