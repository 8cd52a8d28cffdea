using System;
using Lpnn.Probes.Core.Json;
using Lpnn.Probes.Core.Numerics;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests.Support
{
    /// <summary>|actual − expected| ≤ abs + rel·|expected|, as stored in the golden files.</summary>
    public struct Tolerance
    {
        public double Absolute;
        public double Relative;

        public Tolerance(double absolute, double relative)
        {
            Absolute = absolute;
            Relative = relative;
        }

        public static Tolerance FromJson(JsonValue golden)
        {
            golden.TryGet("tolerance", out var t);
            t.TryGet("abs", out var a);
            t.TryGet("rel", out var r);
            return new Tolerance(a.AsNumber, r.AsNumber);
        }

        public void AssertClose(double expected, double actual, string what)
        {
            double allowed = Absolute + Relative * Math.Abs(expected);
            if (!(Math.Abs(actual - expected) <= allowed))
                Assert.Fail(what + ": expected " + InvariantFormat.Number(expected) + ", got " + InvariantFormat.Number(actual) +
                            " (allowed ±" + InvariantFormat.Number(allowed) + ")");
        }
    }

    public static class JsonArrays
    {
        public static double[] Doubles(JsonValue array)
        {
            var result = new double[array.Items.Count];
            for (int i = 0; i < result.Length; i++) result[i] = array.Items[i].AsNumber;
            return result;
        }

        public static float[] Floats(JsonValue array)
        {
            var result = new float[array.Items.Count];
            for (int i = 0; i < result.Length; i++) result[i] = (float)array.Items[i].AsNumber;
            return result;
        }

        public static JsonValue Get(this JsonValue value, string key)
        {
            if (!value.TryGet(key, out var member)) throw new ArgumentException("golden file has no '" + key + "'");
            return member;
        }
    }
}
