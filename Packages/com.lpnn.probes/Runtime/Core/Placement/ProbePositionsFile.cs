using System;
using System.Collections.Generic;
using System.IO;
using System.Numerics;
using System.Text;
using Lpnn.Probes.Core.IO;
using Lpnn.Probes.Core.Json;
using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Core.Placement
{
    /// <summary>The probe positions file (<c>*.probes.json</c>, Documentation~/file-formats.md) that <c>lpnn place</c> and the
    /// editor's batch mode write and the inspector imports into a LightProbeGroup. Positions are world space.</summary>
    public static class ProbePositionsFile
    {
        public const string FormatName = "lpnn.probes";
        public const int FormatVersion = 1;
        public const string Extension = ".probes.json";

        /// <summary>A parsed file: world positions, their unit and the free-form provenance.</summary>
        public sealed class Content
        {
            public Vector3[] Positions { get; }
            public string Units { get; }
            public JsonValue Source { get; }

            public Content(Vector3[] positions, string units, JsonValue source)
            {
                Positions = positions;
                Units = units;
                Source = source;
            }
        }

        public static Content Read(string path)
        {
            string text;
            try
            {
                text = File.ReadAllText(path, Encoding.UTF8);
            }
            catch (Exception e) when (e is IOException || e is UnauthorizedAccessException)
            {
                throw new LpnnException(path + ": cannot read the probe positions file: " + e.Message);
            }
            return Parse(text, path);
        }

        /// <summary>Parses and validates; errors name the file, the field and, for positions, the index.</summary>
        public static Content Parse(string text, string name)
        {
            JsonValue root;
            try
            {
                root = JsonParser.Parse(text ?? "");
            }
            catch (JsonParseException e)
            {
                throw new LpnnException(name + ": " + e.Message);
            }
            if (root.Kind != JsonKind.Object) throw Problem(name, "the file must hold a JSON object");
            if (!root.TryGet("format", out var format) || format.Kind != JsonKind.String || format.AsString != FormatName)
                throw Problem(name, "field 'format' must be \"" + FormatName + "\" (is this a *.probes.json written by `lpnn place`?)");
            if (!root.TryGet("version", out var version) || !version.IsInteger || version.AsNumber != FormatVersion)
                throw Problem(name, "field 'version' must be " + FormatVersion + "; this package reads version " + FormatVersion + " only");
            if (!root.TryGet("space", out var space) || space.Kind != JsonKind.String || space.AsString != "world")
                throw Problem(name, "field 'space' must be \"world\"");
            string units = root.TryGet("units", out var u) && u.Kind == JsonKind.String ? u.AsString : "m";
            if (!root.TryGet("positions", out var list) || list.Kind != JsonKind.Array)
                throw Problem(name, "field 'positions' is missing or not a list");
            var positions = new Vector3[list.Items.Count];
            for (int p = 0; p < positions.Length; p++) positions[p] = ReadPosition(name, p, list.Items[p]);
            if (root.TryGet("count", out var count) && (!count.IsInteger || count.AsNumber != positions.Length))
                throw Problem(name, "field 'count' is " + count + " but 'positions' holds " + positions.Length + " entries (truncated file?)");
            JsonValue source = root.TryGet("source", out var s) && s.Kind == JsonKind.Object ? s : JsonValue.NewObject();
            return new Content(positions, units, source);
        }

        /// <summary>The file text: keys in the documented order, shortest round-trip numbers, invariant culture.</summary>
        public static string Format(IReadOnlyList<Vector3> positions, JsonValue source, string units = "m")
        {
            if (positions == null) throw new ArgumentNullException(nameof(positions));
            var root = JsonValue.NewObject();
            root.Set("format", JsonValue.From(FormatName));
            root.Set("version", JsonValue.From(FormatVersion));
            root.Set("units", JsonValue.From(units ?? "m"));
            root.Set("space", JsonValue.From("world"));
            root.Set("count", JsonValue.From(positions.Count));
            var list = JsonValue.NewArray();
            for (int p = 0; p < positions.Count; p++)
            {
                var v = positions[p];
                if (!Double3.FromVector3(v).IsFinite)
                    throw new LpnnException("probe " + p + " has a non-finite position " + InvariantFormat.Vector(v) + "; nothing was written");
                var triple = JsonValue.NewArray();
                triple.Add(JsonValue.From(v.X));
                triple.Add(JsonValue.From(v.Y));
                triple.Add(JsonValue.From(v.Z));
                list.Add(triple);
            }
            root.Set("positions", list);
            root.Set("source", source ?? JsonValue.NewObject());
            return JsonWriter.Write(root) + "\n";
        }

        /// <summary>Writes (or atomically replaces) a positions file.</summary>
        public static void Save(string path, IReadOnlyList<Vector3> positions, JsonValue source, string units = "m")
        {
            byte[] bytes = new UTF8Encoding(false).GetBytes(Format(positions, source, units));
            AtomicFile.WriteAllBytes(path, bytes);
        }

        private static Vector3 ReadPosition(string name, int index, JsonValue item)
        {
            if (item.Kind != JsonKind.Array || item.Items.Count != 3)
                throw Problem(name, "positions[" + index + "] must be a list of 3 numbers");
            var c = new float[3];
            for (int a = 0; a < 3; a++)
            {
                var v = item.Items[a];
                if (v.Kind != JsonKind.Number) throw Problem(name, "positions[" + index + "][" + a + "] is not a number");
                c[a] = (float)v.AsNumber;
                if (float.IsInfinity(c[a])) throw Problem(name, "positions[" + index + "][" + a + "] " + InvariantFormat.Number(v.AsNumber) + " does not fit a float");
            }
            return new Vector3(c[0], c[1], c[2]);
        }

        private static LpnnException Problem(string name, string what) => new LpnnException(name + ": " + what);
    }
}
