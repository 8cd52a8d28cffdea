using System;
using System.Collections.Generic;
using System.Globalization;
using System.IO;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Json;
using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Core.Captures
{
    /// <summary>Reads the thesis tool's features.txt / comparisons.txt, which it wrote in the machine's locale
    /// ("0,0226", "2,338238E-05"), so old datasets import (Documentation~/file-formats.md, "Legacy").</summary>
    internal static class LegacyThesisFiles
    {
        /// <summary>One float[F] per point. The first non-blank line starts with F; blocks of whitespace-separated
        /// numbers separated by blank lines are points; '.' or ',' is the decimal separator.</summary>
        public static List<float[]> ReadFeatures(string path)
        {
            string[] lines = ReadLines(path);
            int line = 0;
            while (line < lines.Length && lines[line].Trim().Length == 0) line++;
            if (line == lines.Length) throw new CaptureException(path + ": the file is empty; expected the number of values per point on the first line");
            string[] first = Split(lines[line]);
            if (!int.TryParse(first[0], NumberStyles.None, CultureInfo.InvariantCulture, out int featureCount) || featureCount < 1)
                throw new CaptureException(path + ":" + (line + 1) + ": expected the number of values per point, found '" + first[0] + "'");
            var points = new List<float[]>();
            var block = new List<float>();
            int blockStart = -1;
            for (line++; line <= lines.Length; line++)
            {
                bool blank = line == lines.Length || lines[line].Trim().Length == 0;
                if (!blank)
                {
                    if (blockStart < 0) blockStart = line + 1;
                    foreach (string token in Split(lines[line])) block.Add(ParseNumber(path, line + 1, token));
                    continue;
                }
                if (blockStart < 0) continue;
                if (block.Count != featureCount)
                    throw new CaptureException(path + ":" + blockStart + ": point " + points.Count + " has " + block.Count + " values, expected " +
                                               featureCount + " (the count on the first line)");
                points.Add(block.ToArray());
                block.Clear();
                blockStart = -1;
            }
            if (points.Count == 0) throw new CaptureException(path + ": no points after the header line");
            return points;
        }

        /// <summary>One label per non-blank line: True or False, case-insensitive.</summary>
        public static List<bool> ReadLabels(string path)
        {
            string[] lines = ReadLines(path);
            var labels = new List<bool>();
            for (int line = 0; line < lines.Length; line++)
            {
                string text = lines[line].Trim();
                if (text.Length == 0) continue;
                if (string.Equals(text, "true", StringComparison.OrdinalIgnoreCase)) labels.Add(true);
                else if (string.Equals(text, "false", StringComparison.OrdinalIgnoreCase)) labels.Add(false);
                else throw new CaptureException(path + ":" + (line + 1) + ": expected True or False, found '" + text + "'");
            }
            return labels;
        }

        /// <summary>A capture of schema lpnn.thesis30 from the two legacy files (labels optional).</summary>
        public static Capture ToCapture(string featuresPath, string labelsPath, string sceneName)
        {
            var points = ReadFeatures(featuresPath);
            var schema = FeatureSchema.Thesis30;
            if (points[0].Length != schema.Count)
                throw new CaptureException(featuresPath + ": points have " + points[0].Length + " values; the thesis layout has " + schema.Count);
            byte[] labels = null;
            if (labelsPath != null)
            {
                var read = ReadLabels(labelsPath);
                if (read.Count != points.Count)
                    throw new CaptureException(labelsPath + ": " + read.Count + " labels for " + points.Count + " feature blocks in " + featuresPath +
                                               "; both files must come from the same run");
                labels = new byte[read.Count];
                for (int n = 0; n < read.Count; n++) labels[n] = read[n] ? (byte)1 : (byte)0;
            }
            int count = points.Count;
            var ids = new int[3 * count];
            var positions = new float[3 * count];
            var features = new float[count * schema.Count];
            for (int n = 0; n < count; n++)
            {
                ids[3 * n] = n;
                positions[3 * n] = n;
                Array.Copy(points[n], 0, features, n * schema.Count, schema.Count);
            }
            var source = JsonValue.NewObject();
            source.Set("legacy", JsonValue.From(true));
            source.Set("scene", JsonValue.From(sceneName ?? Path.GetFileNameWithoutExtension(featuresPath)));
            source.Set("features_file", JsonValue.From(Path.GetFileName(featuresPath)));
            return new Capture(ids, positions, new float[27 * count], features, schema.Id, schema.Names, 1.0, "m", 1.0, labels,
                labels == null ? null : "legacy:" + Path.GetFileName(labelsPath), source);
        }

        private static string[] ReadLines(string path)
        {
            try
            {
                return File.ReadAllLines(path);
            }
            catch (Exception e) when (e is IOException || e is UnauthorizedAccessException)
            {
                throw new CaptureException(path + ": cannot read: " + e.Message);
            }
        }

        private static string[] Split(string line) => line.Split(new[] { ' ', '\t' }, StringSplitOptions.RemoveEmptyEntries);

        /// <summary>Accepts "0.0226", "0,0226" and "2,338238E-05": a comma can only be a decimal separator here,
        /// because values are whitespace-separated and the tool never wrote thousands separators.</summary>
        private static float ParseNumber(string path, int line, string token)
        {
            if (token.IndexOf(',') >= 0 && token.IndexOf('.') >= 0)
                throw new CaptureException(path + ":" + line + ": '" + token + "' has both ',' and '.'; expected one decimal separator");
            string normalised = token.Replace(',', '.');
            if (!float.TryParse(normalised, NumberStyles.Float, InvariantFormat.Culture, out float value) || float.IsNaN(value) || float.IsInfinity(value))
                throw new CaptureException(path + ":" + line + ": '" + token + "' is not a finite number");
            return value;
        }
    }
}
