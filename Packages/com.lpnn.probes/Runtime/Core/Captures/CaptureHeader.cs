using System;
using System.Collections.Generic;
using System.IO;
using System.Text;
using Lpnn.Probes.Core.IO;
using Lpnn.Probes.Core.Json;
using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Core.Captures
{
    /// <summary>Collects problems: throws at the first one, or keeps them all (validate).</summary>
    internal sealed class ProblemList
    {
        public readonly bool CollectAll;
        public readonly List<string> Items = new List<string>();

        public ProblemList(bool collectAll) { CollectAll = collectAll; }

        public void Add(string message)
        {
            if (!CollectAll) throw new CaptureException(message);
            Items.Add(message);
        }
    }

    /// <summary>Where one section sits in the file.</summary>
    internal sealed class SectionLayout
    {
        public string Name, DType;
        public int[] Shape;
        public long ByteLength;
    }

    /// <summary>The typed, checked header of a capture.</summary>
    internal sealed class HeaderFields
    {
        public int PointCount;
        public string Schema, Units, LabelSource;
        public string[] FeatureNames;
        public double CellSize, LightingScale;
        public JsonValue Source;
        public readonly List<SectionLayout> Sections = new List<SectionLayout>();

        public static HeaderFields Parse(string name, JsonValue header, ProblemList problems)
        {
            bool ok = true;
            Action<string, string> bad = (key, message) =>
            {
                ok = false;
                problems.Add(name + ": header: field '" + key + "': " + message);
            };
            foreach (string key in CaptureFormat.KnownHeaderKeys)
                if (!header.Has(key)) bad(key, "missing");
            if (!ok) return null;
            var fields = new HeaderFields();
            header.TryGet("format", out var format);
            if (format.Kind != JsonKind.String || format.AsString != CaptureFormat.FormatName) bad("format", Show(format) + " is not '" + CaptureFormat.FormatName + "'");
            header.TryGet("version", out var version);
            if (!version.IsInteger || version.AsNumber != CaptureFormat.FormatVersion) bad("version", Show(version) + " does not match the binary version " + CaptureFormat.FormatVersion);
            header.TryGet("point_count", out var count);
            if (!count.IsInteger || count.AsNumber < 1 || count.AsNumber > int.MaxValue / 27) bad("point_count", Show(count) + " is not an integer ≥ 1");
            else fields.PointCount = (int)count.AsNumber;
            header.TryGet("schema", out var schema);
            if (schema.Kind != JsonKind.String || schema.AsString.Length == 0) bad("schema", "must be a non-empty string");
            else fields.Schema = schema.AsString;
            header.TryGet("feature_names", out var names);
            fields.FeatureNames = StringList(names);
            if (fields.FeatureNames == null || fields.FeatureNames.Length == 0) bad("feature_names", "must be a non-empty list of non-empty strings");
            else if (new HashSet<string>(fields.FeatureNames).Count != fields.FeatureNames.Length) bad("feature_names", "has duplicate names");
            header.TryGet("cell_size", out var cell);
            if (cell.Kind != JsonKind.Number || !(cell.AsNumber > 0)) bad("cell_size", Show(cell) + " is not a finite number > 0");
            else fields.CellSize = cell.AsNumber;
            header.TryGet("units", out var units);
            if (units.Kind != JsonKind.String) bad("units", "must be a string");
            else fields.Units = units.AsString;
            header.TryGet("lighting_scale", out var scale);
            if (scale.Kind != JsonKind.Number || !(scale.AsNumber > 0)) bad("lighting_scale", Show(scale) + " is not a finite number > 0");
            else fields.LightingScale = scale.AsNumber;
            header.TryGet("sh_convention", out var convention);
            if (convention.Kind != JsonKind.String || convention.AsString != Capture.ShConvention)
                bad("sh_convention", Show(convention) + " is not '" + Capture.ShConvention + "'");
            header.TryGet("label_source", out var labelSource);
            if (!labelSource.IsNull && labelSource.Kind != JsonKind.String) bad("label_source", "must be a string or null");
            else fields.LabelSource = labelSource.IsNull ? null : labelSource.AsString;
            header.TryGet("source", out var source);
            if (source.Kind != JsonKind.Object) bad("source", "must be an object");
            fields.Source = source;
            header.TryGet("sections", out var sections);
            if (sections.Kind != JsonKind.Array) bad("sections", "must be a list");
            if (!ok) return null;
            return fields.ParseSections(name, sections, problems) ? fields : null;
        }

        private bool ParseSections(string name, JsonValue sections, ProblemList problems)
        {
            bool ok = true;
            var seen = new HashSet<string>();
            for (int position = 0; position < sections.Items.Count; position++)
            {
                string where = name + ": header: sections[" + position + "]";
                var entry = sections.Items[position];
                if (entry.Kind != JsonKind.Object || !entry.TryGet("name", out var sectionName) || !entry.TryGet("dtype", out var dtype) ||
                    !entry.TryGet("shape", out var shape) || sectionName.Kind != JsonKind.String || dtype.Kind != JsonKind.String)
                {
                    problems.Add(where + ": needs a string 'name', a string 'dtype' and a 'shape'");
                    ok = false;
                    continue;
                }
                string section = sectionName.AsString;
                if (!seen.Add(section))
                {
                    problems.Add(where + ": name '" + section + "' is repeated");
                    ok = false;
                    continue;
                }
                int itemSize = dtype.AsString == "int32" || dtype.AsString == "float32" ? 4 : dtype.AsString == "uint8" ? 1 : 0;
                if (itemSize == 0)
                {
                    problems.Add(where + " ('" + section + "'): dtype '" + dtype.AsString + "' is not one of float32, int32, uint8");
                    ok = false;
                    continue;
                }
                int[] dims = IntList(shape);
                if (dims == null || dims.Length == 0)
                {
                    problems.Add(where + " ('" + section + "'): shape is not a list of non-negative integers");
                    ok = false;
                    continue;
                }
                string expected = ExpectedLayout(section);
                string actualLayout = dtype.AsString + " [" + string.Join(", ", Array.ConvertAll(dims, d => d.ToString(InvariantFormat.Culture))) + "]";
                if (expected != null && expected != actualLayout)
                {
                    problems.Add(where + " ('" + section + "'): is " + actualLayout + ", expected " + expected);
                    ok = false;
                    continue;
                }
                if (expected == null && dims[0] != PointCount)
                {
                    problems.Add(where + " ('" + section + "'): first dimension " + dims[0] + " is not point_count " + PointCount);
                    ok = false;
                    continue;
                }
                long bytes = itemSize;
                foreach (int d in dims) bytes *= d;
                if (bytes > int.MaxValue)
                {
                    problems.Add(where + " ('" + section + "'): " + InvariantFormat.Count(bytes) + " bytes is more than one file section may hold");
                    ok = false;
                    continue;
                }
                Sections.Add(new SectionLayout { Name = section, DType = dtype.AsString, Shape = dims, ByteLength = bytes });
            }
            foreach (string required in new[] { "ids", "positions", "sh", "features" })
            {
                if (seen.Contains(required)) continue;
                problems.Add(name + ": header: sections: required section '" + required + "' is missing");
                ok = false;
            }
            if (seen.Contains("labels") && LabelSource == null)
                problems.Add(name + ": header: field 'label_source': must be set when a 'labels' section exists");
            return ok;
        }

        private string ExpectedLayout(string section)
        {
            string n = PointCount.ToString(InvariantFormat.Culture);
            switch (section)
            {
                case "ids": return "int32 [" + n + ", 3]";
                case "positions": return "float32 [" + n + ", 3]";
                case "sh": return "float32 [" + n + ", 27]";
                case "features": return "float32 [" + n + ", " + FeatureNames.Length.ToString(InvariantFormat.Culture) + "]";
                case "labels": return "uint8 [" + n + "]";
                default: return null;
            }
        }

        private static string[] StringList(JsonValue value)
        {
            if (value.Kind != JsonKind.Array) return null;
            var result = new string[value.Items.Count];
            for (int i = 0; i < result.Length; i++)
            {
                var item = value.Items[i];
                if (item.Kind != JsonKind.String || item.AsString.Length == 0) return null;
                result[i] = item.AsString;
            }
            return result;
        }

        private static int[] IntList(JsonValue value)
        {
            if (value.Kind != JsonKind.Array) return null;
            var result = new int[value.Items.Count];
            for (int i = 0; i < result.Length; i++)
            {
                var item = value.Items[i];
                if (!item.IsInteger || item.AsNumber < 0 || item.AsNumber > int.MaxValue) return null;
                result[i] = (int)item.AsNumber;
            }
            return result;
        }

        private static string Show(JsonValue value) => JsonWriter.Write(value);
    }
}
