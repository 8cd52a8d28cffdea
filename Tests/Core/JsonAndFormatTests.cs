using System;
using System.Collections.Generic;
using System.Globalization;
using System.Threading;
using Lpnn.Probes.Core.Json;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Tests.Support;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    [TestFixture]
    public class JsonAndFormatTests
    {
        private CultureInfo _culture;

        [SetUp]
        public void UseACommaDecimalCulture()
        {
            // The thesis tool wrote "0,0226" under a Greek locale: every test here runs under one.
            _culture = Thread.CurrentThread.CurrentCulture;
            Thread.CurrentThread.CurrentCulture = new CultureInfo("el-GR");
        }

        [TearDown]
        public void RestoreCulture() => Thread.CurrentThread.CurrentCulture = _culture;

        [Test]
        public void MedianTakesTheMiddleOrTheMeanOfTheTwoMiddleValuesAndKeepsItsInput()
        {
            var odd = new[] { 3.0, -1.0, 2.0 };
            Assert.That(Statistics.Median(odd), Is.EqualTo(2.0));
            Assert.That(odd, Is.EqualTo(new[] { 3.0, -1.0, 2.0 }));
            Assert.That(Statistics.Median(new List<double> { 4.0, 1.0, 3.0, 2.0 }), Is.EqualTo(2.5));
            Assert.Throws<ArgumentException>(() => Statistics.Median(new double[0]));
            Assert.Throws<ArgumentException>(() => Statistics.Median(new[] { 1.0, double.NaN, 2.0 }));
        }

        [Test]
        public void MedianBySelectionEqualsTheMiddleOfTheSortedValues()
        {
            var random = new Random(3);
            foreach (int count in new[] { 1, 2, 3, 10, 11, 257, 1000, 1001 })
            {
                foreach (int distinct in new[] { 1, 2, 7, 1000000 })
                {
                    var values = new double[count];
                    for (int n = 0; n < count; n++) values[n] = random.Next(distinct) * 0.37 - 5;
                    var sorted = (double[])values.Clone();
                    Array.Sort(sorted);
                    double expected = count % 2 == 1 ? sorted[count / 2] : (sorted[count / 2 - 1] + sorted[count / 2]) / 2;
                    Assert.That(Statistics.Median(values), Is.EqualTo(expected), count + " values, " + distinct + " distinct");
                }
            }
        }

        [Test]
        public void NumbersAreWrittenWithADotAndParsedBackExactly()
        {
            foreach (double value in new[] { 0.0226, 2.338238e-05, 1e6, -1.5, 0.1, 1.0 / 3 })
            {
                string text = InvariantFormat.Number(value);
                StringAssert.DoesNotContain(",", text);
                Assert.That(double.Parse(text, CultureInfo.InvariantCulture), Is.EqualTo(value));
            }
            Assert.That(InvariantFormat.Number(0.1f), Is.EqualTo("0.1"));
            Assert.That(InvariantFormat.Count(2000000), Is.EqualTo("2,000,000"));
        }

        [Test]
        public void JsonRoundTripKeepsKeyOrderAndValues()
        {
            const string text = "{\"b\": 1.5, \"a\": [1, -2e-05, true, null, \"x\\\"y\\n\"], \"c\": {}}";
            var value = JsonParser.Parse(text);
            Assert.That(value.Members[0].Key, Is.EqualTo("b"));
            Assert.That(JsonWriter.Write(value), Is.EqualTo("{\"b\": 1.5, \"a\": [1, -2E-05, true, null, \"x\\\"y\\n\"], \"c\": {}}"));
            Assert.That(JsonParser.Parse(JsonWriter.Write(value)).Get("a").Items[1].AsNumber, Is.EqualTo(-2e-05));
        }

        [Test]
        public void MalformedJsonNamesLineAndColumn()
        {
            var error = Assert.Throws<JsonParseException>(() => JsonParser.Parse("{\n  \"a\": 1,\n  \"b\" 2\n}"));
            Assert.That(error.Line, Is.EqualTo(3));
            Assert.That(error.Column, Is.EqualTo(7));
            StringAssert.Contains("expected ':'", error.Message);
            Assert.Throws<JsonParseException>(() => JsonParser.Parse("[1, 2,]"));
            Assert.Throws<JsonParseException>(() => JsonParser.Parse("{\"a\": NaN}"));
            Assert.Throws<JsonParseException>(() => JsonParser.Parse("{\"a\": 1, \"a\": 2}"));
            Assert.Throws<JsonParseException>(() => JsonParser.Parse("1e400"));
        }

        [Test]
        public void JsonRefusesNonFiniteNumbers()
        {
            Assert.Throws<System.ArgumentException>(() => JsonValue.From(double.NaN));
            Assert.Throws<System.ArgumentException>(() => JsonValue.From(double.PositiveInfinity));
        }

        [TestCase(0.1234, 0.124)]
        [TestCase(0.19, 0.19)]
        [TestCase(1234.5, 1240)]
        [TestCase(0.000123456, 0.000124)]
        public void RoundUpSignificantNeverGoesBelowTheValue(double value, double expected)
        {
            double rounded = InvariantFormat.RoundUpSignificant(value, 3);
            Assert.That(rounded, Is.EqualTo(expected).Within(expected * 1e-12));
            Assert.That(rounded, Is.GreaterThanOrEqualTo(value));
        }
    }
}
