// Measures whether Newtonsoft.Json (Json.NET) can replace Runtime/Core/Json (issue 17 item 18). Not part of the package;
// run with Tools~/experiments/json-comparison/run.sh (Json.NET 6.0.8 from Debian, installed by Tools~/install-system.sh;
// make test smoke-tests it: Training~/tests/tools/test_json_comparison.py).
// Prints: (1) every number of the golden files and the model card parsed by both libraries, round trips, parse times, in
// en-US and de-DE; (2) what Json.NET's reader accepts that the cross-language contracts forbid; (3) whether Json.NET's writer
// reproduces the capture header that Python's json.dumps wrote (the C# encoder must, byte for byte).
using System;
using System.Collections.Generic;
using System.Diagnostics;
using System.Globalization;
using System.IO;
using System.Text;
using System.Threading;
using Lpnn.Probes.Core.Json;
using Newtonsoft.Json.Linq;
using Formatting = Newtonsoft.Json.Formatting;
using JsonTextReader = Newtonsoft.Json.JsonTextReader;
using FloatParseHandling = Newtonsoft.Json.FloatParseHandling;
using DateParseHandling = Newtonsoft.Json.DateParseHandling;

static class JsonLibraryComparison
{
    static JToken ReadNewtonsoft(string text)
    {
        using (var reader = new JsonTextReader(new StringReader(text)) { FloatParseHandling = FloatParseHandling.Double, DateParseHandling = DateParseHandling.None })
            return JToken.ReadFrom(reader);
    }

    static void Numbers(JsonValue v, List<double> into)
    {
        if (v.Kind == JsonKind.Number) into.Add(v.AsNumber);
        else if (v.Kind == JsonKind.Array) foreach (var i in v.Items) Numbers(i, into);
        else if (v.Kind == JsonKind.Object) foreach (var m in v.Members) Numbers(m.Value, into);
    }

    static void Numbers(JToken t, List<double> into)
    {
        if (t.Type == JTokenType.Float || t.Type == JTokenType.Integer) { into.Add(t.Value<double>()); return; }
        foreach (var c in t.Children()) Numbers(c, into);
    }

    static void CompareNumbers(string[] files)
    {
        foreach (var culture in new[] { "en-US", "de-DE" })
        {
            Thread.CurrentThread.CurrentCulture = new CultureInfo(culture);
            foreach (var path in files)
            {
                string text = File.ReadAllText(path);
                var ours = JsonParser.Parse(text);
                var theirs = ReadNewtonsoft(text);
                var a = new List<double>(); var b = new List<double>(); Numbers(ours, a); Numbers(theirs, b);
                int differ = 0;
                for (int i = 0; i < Math.Min(a.Count, b.Count); i++) if (!a[i].Equals(b[i])) differ++;
                var oursBack = new List<double>(); Numbers(JsonParser.Parse(JsonWriter.Write(ours)), oursBack);
                var theirsBack = new List<double>(); Numbers(JsonParser.Parse(theirs.ToString(Formatting.None)), theirsBack);
                int oursLost = 0, theirsLost = 0;
                for (int i = 0; i < a.Count; i++)
                {
                    if (!a[i].Equals(oursBack[i])) oursLost++;
                    if (i >= theirsBack.Count || !a[i].Equals(theirsBack[i])) theirsLost++;
                }
                var watch = Stopwatch.StartNew();
                for (int r = 0; r < 5; r++) JsonParser.Parse(text);
                double oursMs = watch.Elapsed.TotalMilliseconds / 5;
                watch.Restart();
                for (int r = 0; r < 5; r++) ReadNewtonsoft(text);
                double theirsMs = watch.Elapsed.TotalMilliseconds / 5;
                Console.WriteLine(string.Format(CultureInfo.InvariantCulture,
                    "{0} {1}: {2} numbers ({3} Json.NET), read differently {4}; changed by a write+read: ours {5}, Json.NET {6}; read ms ours {7:F1}, Json.NET {8:F1}",
                    culture, Path.GetFileName(path), a.Count, b.Count, differ, oursLost, theirsLost, oursMs, theirsMs));
            }
        }
        Thread.CurrentThread.CurrentCulture = CultureInfo.InvariantCulture;
    }

    static void InvalidInputs()
    {
        foreach (var text in new[] { "[1, 2,]", "{\"a\": NaN}", "{\"a\": Infinity}", "{\"a\": 1, \"a\": 2}", "1e400", "[1] x", "{'a': 1}", "{a: 1}", "// c\n[1]" })
        {
            string ours, theirs;
            try { JsonParser.Parse(text); ours = "ACCEPTED"; } catch (JsonParseException) { ours = "refused"; }
            try { theirs = "ACCEPTED as " + ReadNewtonsoft(text).ToString(Formatting.None); } catch (Exception e) { theirs = "refused (" + e.GetType().Name + ")"; }
            Console.WriteLine("{0,-20} ours: {1,-9} Json.NET: {2}", text.Replace("\n", " "), ours, theirs);
        }
    }

    static void CaptureHeader(string capturePath)
    {
        byte[] bytes = File.ReadAllBytes(capturePath);
        string rest = Encoding.UTF8.GetString(bytes, 16, bytes.Length - 16);  // the header follows the 16-byte prefix
        int depth = 0, end = 0; bool inString = false;
        for (int i = 0; i < rest.Length && end == 0; i++)
        {
            char c = rest[i];
            if (inString) { if (c == '\\') i++; else if (c == '"') inString = false; continue; }
            if (c == '"') inString = true;
            else if (c == '{') depth++;
            else if (c == '}' && --depth == 0) end = i + 1;
        }
        string header = rest.Substring(0, end);
        string ours = JsonWriter.Write(JsonParser.Parse(header));
        string theirs = ReadNewtonsoft(header).ToString(Formatting.None);
        Console.WriteLine("capture header written by Python ({0} chars): our writer reproduces it: {1}; Json.NET's: {2} ({3} chars, starts {4})",
            header.Length, ours == header, theirs == header, theirs.Length, theirs.Substring(0, Math.Min(40, theirs.Length)));
    }

    static void Main(string[] args)
    {
        CompareNumbers(args[0].Split(';'));
        InvalidInputs();
        CaptureHeader(args[1]);
    }
}
