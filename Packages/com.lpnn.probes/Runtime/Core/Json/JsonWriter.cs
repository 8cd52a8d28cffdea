using System.Text;
using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Core.Json
{
    /// <summary>Serialises JSON deterministically: key order as stored, shortest round-trip numbers,
    /// invariant culture, ", " and ": " separators on one line (or indented when asked).</summary>
    internal static class JsonWriter
    {
        public static string Write(JsonValue value, bool indented = false)
        {
            var builder = new StringBuilder();
            Append(builder, value, indented, 0);
            return builder.ToString();
        }

        private static void Append(StringBuilder builder, JsonValue value, bool indented, int depth)
        {
            switch (value.Kind)
            {
                case JsonKind.Null: builder.Append("null"); break;
                case JsonKind.Boolean: builder.Append(value.AsBoolean ? "true" : "false"); break;
                case JsonKind.Number: builder.Append(FormatNumber(value.AsNumber)); break;
                case JsonKind.String: AppendString(builder, value.AsString); break;
                case JsonKind.Array:
                    builder.Append('[');
                    for (int i = 0; i < value.Items.Count; i++)
                    {
                        if (i > 0) builder.Append(indented ? "," : ", ");
                        NewLine(builder, indented, depth + 1);
                        Append(builder, value.Items[i], indented, depth + 1);
                    }
                    if (value.Items.Count > 0) NewLine(builder, indented, depth);
                    builder.Append(']');
                    break;
                default:
                    builder.Append('{');
                    for (int i = 0; i < value.Members.Count; i++)
                    {
                        if (i > 0) builder.Append(indented ? "," : ", ");
                        NewLine(builder, indented, depth + 1);
                        AppendString(builder, value.Members[i].Key);
                        builder.Append(": ");
                        Append(builder, value.Members[i].Value, indented, depth + 1);
                    }
                    if (value.Members.Count > 0) NewLine(builder, indented, depth);
                    builder.Append('}');
                    break;
            }
        }

        /// <summary>Integers print without a fraction ("3", not "3.0"); everything else shortest round-trip.</summary>
        public static string FormatNumber(double number)
        {
            if (number == System.Math.Floor(number) && System.Math.Abs(number) < 1e15)
                return ((long)number).ToString(InvariantFormat.Culture);
            return InvariantFormat.Number(number);
        }

        private static void NewLine(StringBuilder builder, bool indented, int depth)
        {
            if (!indented) return;
            builder.Append('\n');
            builder.Append(' ', depth * 2);
        }

        private static void AppendString(StringBuilder builder, string text)
        {
            builder.Append('"');
            foreach (char c in text)
            {
                switch (c)
                {
                    case '"': builder.Append("\\\""); break;
                    case '\\': builder.Append("\\\\"); break;
                    case '\n': builder.Append("\\n"); break;
                    case '\r': builder.Append("\\r"); break;
                    case '\t': builder.Append("\\t"); break;
                    default:
                        if (c < 0x20) builder.Append("\\u").Append(((int)c).ToString("x4", InvariantFormat.Culture));
                        else builder.Append(c);
                        break;
                }
            }
            builder.Append('"');
        }
    }
}
