using System;
using System.Collections.Generic;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Sh;

namespace Lpnn.Probes.Core.Captures
{
    /// <summary>Value-level checks of a capture, shared by reading, validating and writing (nothing invalid is
    /// ever written). Each problem names the file, the record (index and id) and the field.</summary>
    internal static class CaptureContent
    {
        private const int MaxProblemsPerKind = 20;

        /// <summary>Collects problems; with <paramref name="stopAtFirst"/> the caller raises the first one.</summary>
        public static List<string> Problems(Capture capture, string name, bool stopAtFirst)
        {
            var problems = new List<string>();
            int n = capture.PointCount, f = capture.FeatureNames.Count;
            if (n < 1) return Add(problems, name + ": capture has no points");
            if (capture.Ids.Length != 3 * n) return Add(problems, name + ": section 'ids' needs 3 values per point");
            if (capture.Positions.Length != 3L * n) return Add(problems, name + ": section 'positions' has " + capture.Positions.Length + " values, expected " + 3L * n);
            if (capture.Sh.Length != 27L * n) return Add(problems, name + ": section 'sh' has " + capture.Sh.Length + " values, expected " + 27L * n);
            if (capture.Features.Length != (long)f * n) return Add(problems, name + ": section 'features' has " + capture.Features.Length + " values, expected " + (long)f * n);
            if (capture.Labels != null && capture.Labels.Length != n) return Add(problems, name + ": section 'labels' has " + capture.Labels.Length + " values, expected " + n);
            if (!(capture.CellSize > 0) || double.IsInfinity(capture.CellSize))
                return Add(problems, name + ": header: field 'cell_size': " + InvariantFormat.Number(capture.CellSize) + " is not a finite number > 0");

            bool stop = false;
            if (!(capture.LightingScale > 0) || double.IsInfinity(capture.LightingScale))
                stop = Report(problems, stopAtFirst, name + ": header: field 'lighting_scale': " + InvariantFormat.Number(capture.LightingScale) + " is not a finite number > 0");
            if (!stop && (f == 0 || new HashSet<string>(capture.FeatureNames).Count != f))
                stop = Report(problems, stopAtFirst, name + ": header: field 'feature_names': must be unique and non-empty");
            var known = FeatureSchema.ById(capture.Schema);
            if (!stop && known != null && !known.NamesMatch(capture.FeatureNames))
                stop = Report(problems, stopAtFirst, name + ": header: field 'feature_names': do not match schema '" + known.Id + "' (" + known.Count + " names)");
            if (!stop && capture.Labels != null && capture.LabelSource == null)
                stop = Report(problems, stopAtFirst, name + ": header: field 'label_source': must be set when labels are present");
            if (stop) return problems;

            int reported = 0;
            for (int p = 1; p < n && reported < MaxProblemsPerKind; p++)
            {
                int order = CompareIds(capture.Ids, p - 1, p);
                if (order < 0) continue;
                reported++;
                string what = order == 0 ? "repeats" : "is out of grid order after";
                if (Report(problems, stopAtFirst, Record(name, capture, p) + ": field 'ids': " + what + " record " + (p - 1))) return problems;
            }
            if (CheckFinite(problems, stopAtFirst, name, capture, capture.Positions, 3, c => "positions[" + "xyz"[c] + "]")) return problems;
            if (CheckFinite(problems, stopAtFirst, name, capture, capture.Sh, ShMath.FloatsPerProbe,
                    c => "sh[" + "rgb"[c / ShMath.CoefficientsPerChannel] + "," + (c % ShMath.CoefficientsPerChannel) + "]")) return problems;
            if (CheckFinite(problems, stopAtFirst, name, capture, capture.Features, f, c => "features[" + capture.FeatureNames[c] + "]")) return problems;

            reported = 0;
            double h = capture.CellSize;
            for (int p = 0; p < n && reported < MaxProblemsPerKind; p++)
            {
                for (int axis = 0; axis < 3; axis++)
                {
                    double expected = h * capture.Ids[3 * p + axis];
                    double actual = capture.Positions[3 * p + axis];
                    double tolerance = 1e-4 * h + 4 * FloatSpacing((float)Math.Abs(expected));
                    if (Math.Abs(actual - expected) <= tolerance) continue;
                    reported++;
                    if (Report(problems, stopAtFirst, Record(name, capture, p) + ": field 'positions[" + "xyz"[axis] + "]': " +
                                                      InvariantFormat.Number(actual) + " is not cell_size × id = " + InvariantFormat.Number(expected)))
                        return problems;
                    break;
                }
            }

            if (capture.Labels != null)
            {
                reported = 0;
                for (int p = 0; p < n && reported < MaxProblemsPerKind; p++)
                {
                    if (capture.Labels[p] <= 1) continue;
                    reported++;
                    if (Report(problems, stopAtFirst, Record(name, capture, p) + ": field 'labels': " + capture.Labels[p] + " is not 0 or 1")) return problems;
                }
            }
            return problems;
        }

        private static bool CheckFinite(List<string> problems, bool stopAtFirst, string name, Capture capture, float[] values, int width,
            Func<int, string> column)
        {
            int reported = 0;
            for (long v = 0; v < values.Length && reported < MaxProblemsPerKind; v++)
            {
                float value = values[v];
                if (!float.IsNaN(value) && !float.IsInfinity(value)) continue;
                reported++;
                if (Report(problems, stopAtFirst, Record(name, capture, (int)(v / width)) + ": field '" + column((int)(v % width)) + "': " +
                                                  InvariantFormat.Number(value) + " is not finite"))
                    return true;
            }
            return false;
        }

        private static int CompareIds(int[] ids, int a, int b)
        {
            for (int axis = 2; axis >= 0; axis--)
            {
                int x = ids[3 * a + axis], y = ids[3 * b + axis];
                if (x != y) return x < y ? -1 : 1;
            }
            return 0;
        }

        /// <summary>Distance from |x| to the next float (one unit in the last place).</summary>
        private static double FloatSpacing(float x)
        {
            int bits = BitConverter.ToInt32(BitConverter.GetBytes(x), 0);
            float next = BitConverter.ToSingle(BitConverter.GetBytes(bits + 1), 0);
            return (double)next - x;
        }

        public static string Record(string name, Capture capture, int point) =>
            name + ": record " + point + " (id " + capture.Ids[3 * point].ToString(InvariantFormat.Culture) + "," +
            capture.Ids[3 * point + 1].ToString(InvariantFormat.Culture) + "," + capture.Ids[3 * point + 2].ToString(InvariantFormat.Culture) + ")";

        private static List<string> Add(List<string> problems, string message)
        {
            problems.Add(message);
            return problems;
        }

        private static bool Report(List<string> problems, bool stopAtFirst, string message)
        {
            problems.Add(message);
            return stopAtFirst;
        }
    }
}
