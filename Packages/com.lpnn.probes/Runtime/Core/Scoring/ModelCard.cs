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

        /// <summary>Parses and checks a card's own consistency; throws <see cref="ModelCardException"/> naming the
        /// card, the field and what to do.</summary>
        public static ModelCard Parse(string json, string source)
        {
            source = string.IsNullOrEmpty(source) ? "model card" : source;
            JsonValue root;
            try
            {
                root = JsonParser.Parse(json ?? "");
            }
            catch (JsonParseException e)
            {
                throw new ModelCardException(source + ": " + e.Message + "; assign the .card.json written beside the model by `lpnn export`");
            }
            if (root.Kind != JsonKind.Object)
                throw Problem(source, "the card must be a JSON object");
            string format = RequireString(root, "format", source);
            double version = RequireNumber(root, "version", source);
            if (format != FormatName || version != FormatVersion)
                throw Problem(source, "format '" + format + "' version " + InvariantFormat.Number(version) + " is not '" + FormatName +
                                      "' version " + FormatVersion);
            string modelFile = RequireString(root, "model_file", source);
            string schema = RequireString(root, "schema", source);
            var names = RequireNames(root, source);
            double count = RequireNumber(root, "feature_count", source);
            if (count != names.Length)
                throw Problem(source, "'feature_count' " + InvariantFormat.Number(count) + " differs from the " + names.Length + " feature names");
            string input = RequireString(RequireObject(root, "input", source), "name", source, "input.name");
            string output = RequireString(RequireObject(root, "output", source), "name", source, "output.name");
            if (input != ContractInputName || output != ContractOutputName)
                throw Problem(source, "the graph's input/output are '" + input + "'/'" + output + "', but the model contract requires '" +
                                      ContractInputName + "'/'" + ContractOutputName + "'");
            return new ModelCard(source, modelFile, schema, names, input, output);
        }

        /// <summary>Stops scoring unless the features are exactly what the model reads (schema id, count and names, in
        /// order); the error names both schemas (the same rule as the trainer's check).</summary>
        public void CheckFeatures(FeatureSchema schema)
        {
            if (schema == null) throw new System.ArgumentNullException(nameof(schema));
            if (schema.Id != Schema || schema.Count != FeatureCount)
            {
                throw new ModelCardException(
                    "the features have schema '" + schema.Id + "' (" + schema.Count + " features) but the model '" + ModelFile + "' (card " +
                    Source + ") expects schema '" + Schema + "' (" + FeatureCount + " features); use a model trained on '" + schema.Id +
                    "' (e.g. the shipped lpnn_default) or retrain with `lpnn train` on captures of '" + schema.Id + "'");
            }
            for (int f = 0; f < FeatureCount; f++)
            {
                if (FeatureNames[f] == schema.Names[f]) continue;
                throw new ModelCardException(
                    "the features and the model '" + ModelFile + "' (card " + Source + ") both use schema '" + Schema + "', but feature " + f +
                    " is '" + schema.Names[f] + "' in the extractor and '" + FeatureNames[f] + "' in the model; the card does not belong to this " +
                    "package version: re-export the model or update the package");
            }
        }

        private static ModelCardException Problem(string source, string what) =>
            new ModelCardException(source + ": " + what + "; assign the .card.json written beside the model by `lpnn export`");

        private static string RequireString(JsonValue obj, string key, string source, string label = null)
        {
            if (!obj.TryGet(key, out var value) || value.Kind != JsonKind.String)
                throw Problem(source, "field '" + (label ?? key) + "' is missing or not a string");
            return value.AsString;
        }

        private static double RequireNumber(JsonValue obj, string key, string source)
        {
            if (!obj.TryGet(key, out var value) || !value.IsInteger)
                throw Problem(source, "field '" + key + "' is missing or not a whole number");
            return value.AsNumber;
        }

        private static JsonValue RequireObject(JsonValue obj, string key, string source)
        {
            if (!obj.TryGet(key, out var value) || value.Kind != JsonKind.Object)
                throw Problem(source, "field '" + key + "' is missing or not an object");
            return value;
        }

        private static string[] RequireNames(JsonValue root, string source)
        {
            if (!root.TryGet("feature_names", out var value) || value.Kind != JsonKind.Array || value.Items.Count == 0)
                throw Problem(source, "field 'feature_names' is missing, empty or not a list");
            var names = new string[value.Items.Count];
            for (int f = 0; f < names.Length; f++)
            {
                var item = value.Items[f];
                if (item.Kind != JsonKind.String || item.AsString.Length == 0)
                    throw Problem(source, "feature_names[" + f + "] is not a non-empty string");
                names[f] = item.AsString;
            }
            return names;
        }
    }
}
