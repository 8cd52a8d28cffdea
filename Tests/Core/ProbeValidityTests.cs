using System;
using System.Numerics;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Json;
using Lpnn.Probes.Core.Tests.Support;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    [TestFixture]
    public class ProbeValidityTests
    {
        private static Vector3[] Vectors(JsonValue array)
        {
            var result = new Vector3[array.Items.Count];
            for (int i = 0; i < result.Length; i++)
            {
                var v = array.Items[i].Items;
                result[i] = new Vector3((float)v[0].AsNumber, (float)v[1].AsNumber, (float)v[2].AsNumber);
            }
            return result;
        }

        [Test]
        public void EveryGoldenCase()
        {
            var golden = TestData.ReadJson("validity_golden.json");
            Assert.That(golden.Get("threshold").AsNumber, Is.EqualTo(ProbeValidity.BackFaceThreshold));
            Assert.That(golden.Get("ray_length").AsNumber, Is.EqualTo((double)ProbeValidity.RayLength));
            Assert.That(golden.Get("capture_section").AsString, Is.EqualTo(ProbeValidity.CaptureSection));
            var cases = golden.Get("cases").Items;
            Assert.That(cases.Count, Is.GreaterThanOrEqualTo(7));
            foreach (var c in cases)
            {
                var hitsJson = c.Get("hits").Items;
                var hits = new bool[hitsJson.Count];
                for (int i = 0; i < hits.Length; i++) hits[i] = hitsJson[i].AsBoolean;
                double fraction = ProbeValidity.BackFaceFraction(Vectors(c.Get("directions")), hits, Vectors(c.Get("normals")));
                string name = c.Get("name").AsString;
                Assert.That(fraction, Is.EqualTo(c.Get("back_face_fraction").AsNumber).Within(1e-12), name);
                Assert.That(ProbeValidity.IsInvalid(fraction), Is.EqualTo(c.Get("invalid").AsBoolean), name);
            }
        }

        [Test]
        public void BadInputsNameTheProblem()
        {
            Assert.Throws<ArgumentException>(() => ProbeValidity.BackFaceFraction(new Vector3[0], new bool[0], new Vector3[0]));
            var error = Assert.Throws<ArgumentException>(() => ProbeValidity.BackFaceFraction(new Vector3[2], new bool[2], new Vector3[1]));
            StringAssert.Contains("differ in length", error.Message);
        }
    }
}
