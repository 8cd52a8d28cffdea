using System;
using System.Numerics;
using Lpnn.Probes.Core.Sh;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    [TestFixture]
    public class ShMathTests
    {
        private static float[] RandomSh(int seed)
        {
            var random = new Random(seed);
            var sh = new float[27];
            for (int c = 0; c < 27; c++) sh[c] = (float)(random.NextDouble() * 2 - 1);
            return sh;
        }

        [Test]
        public void EvaluateMultipliesEachCoefficientByItsUnityPolynomial()
        {
            // One coefficient at a time: the result must be exactly that polynomial of the direction.
            var direction = Vector3.Normalize(new Vector3(0.3f, -0.5f, 0.8f));
            double x = direction.X, y = direction.Y, z = direction.Z;
            double[] polynomials = { 1, y, z, x, x * y, y * z, 3 * z * z - 1, x * z, x * x - y * y };
            for (int channel = 0; channel < 3; channel++)
            {
                for (int i = 0; i < 9; i++)
                {
                    var sh = new float[27];
                    sh[ShMath.Index(channel, i)] = 2f;
                    ShMath.Evaluate(sh, 0, x, y, z, out double r, out double g, out double b);
                    double[] rgb = { r, g, b };
                    for (int c = 0; c < 3; c++)
                        Assert.That(rgb[c], Is.EqualTo(c == channel ? 2 * polynomials[i] : 0).Within(1e-12), "channel " + channel + " coefficient " + i);
                }
            }
        }

        [Test]
        public void DirectionalLightEvaluatesToTwiceIntensityTimesColourTowardTheLightAndOneSeventeenthAway()
        {
            var probe = new ShL2();
            var direction = Vector3.Normalize(new Vector3(1, 2, -0.5f));
            var colour = new Vector3(0.8f, 0.4f, 0.2f);
            probe.AddDirectionalLight(direction, colour, 1.5f);
            var toward = probe.Evaluate(direction);
            var away = probe.Evaluate(-direction);
            var k = colour * 3f;
            Assert.That(toward.X, Is.EqualTo(k.X).Within(1e-5));
            Assert.That(toward.Y, Is.EqualTo(k.Y).Within(1e-5));
            Assert.That(toward.Z, Is.EqualTo(k.Z).Within(1e-5));
            Assert.That(away.X, Is.EqualTo(k.X / 17).Within(1e-5));
            Assert.That(away.Z, Is.EqualTo(k.Z / 17).Within(1e-5));
        }

        [Test]
        public void DirectionalLightNormalisesItsDirectionAndRejectsZero()
        {
            var a = new ShL2();
            var b = new ShL2();
            a.AddDirectionalLight(new Vector3(0, 0, 1), Vector3.One, 1);
            b.AddDirectionalLight(new Vector3(0, 0, 7), Vector3.One, 1);
            Assert.That(a.Equals(b), Is.True);
            Assert.Throws<ArgumentException>(() => a.AddDirectionalLight(Vector3.Zero, Vector3.One, 1));
        }

        [Test]
        public void AmbientLightIsTheSameInEveryDirection()
        {
            var probe = new ShL2();
            probe.AddAmbientLight(new Vector3(0.25f, 0.5f, 1f));
            foreach (var d in new[] { Vector3.UnitX, -Vector3.UnitY, Vector3.Normalize(new Vector3(1, 1, 1)) })
            {
                var value = probe.Evaluate(d);
                Assert.That(value.X, Is.EqualTo(0.25f).Within(1e-7));
                Assert.That(value.Y, Is.EqualTo(0.5f).Within(1e-7));
                Assert.That(value.Z, Is.EqualTo(1f).Within(1e-7));
            }
        }

        [Test]
        public void AmbientPlusDirectedFitsTheQuakeShadingFunctionAsDocumented()
        {
            // a + d·max(0, n·l) fitted in L2: response 3/32 + c/2 + 15c²/32 of the directed part (sh.md).
            var sh = new float[27];
            var l = Vector3.Normalize(new Vector3(0.2f, 0.9f, -0.4f));
            ShMath.AmbientPlusDirected(new Vector3(0.1f, 0.2f, 0.3f), new Vector3(1f, 0.5f, 0.25f), l, sh, 0);
            foreach (double c in new[] { 1.0, 0.0, -1.0 })
            {
                // a direction at angle acos(c) from l, in the plane of l and a perpendicular axis
                var perpendicular = Vector3.Normalize(Vector3.Cross(l, Vector3.UnitX));
                var n = Vector3.Normalize((float)c * l + (float)Math.Sqrt(1 - c * c) * perpendicular);
                double response = 3.0 / 32 + c / 2 + 15 * c * c / 32;
                var value = ShMath.Evaluate(sh, 0, n);
                Assert.That(value.X, Is.EqualTo(0.1 + 1.0 * response).Within(1e-5), "c = " + c);
                Assert.That(value.Z, Is.EqualTo(0.3 + 0.25 * response).Within(1e-5), "c = " + c);
            }
        }

        [Test]
        public void BlendIsLinearInTheProbes()
        {
            var a = new ShL2(RandomSh(1));
            var b = new ShL2(RandomSh(2));
            var d = Vector3.Normalize(new Vector3(-0.3f, 0.2f, 0.9f));
            var blended = ShL2.Blend(new[] { a, b }, new[] { 0.25, 0.75 });
            var expected = 0.25f * a.Evaluate(d) + 0.75f * b.Evaluate(d);
            var actual = blended.Evaluate(d);
            Assert.That(actual.X, Is.EqualTo(expected.X).Within(1e-5));
            Assert.That(actual.Y, Is.EqualTo(expected.Y).Within(1e-5));
            Assert.That(actual.Z, Is.EqualTo(expected.Z).Within(1e-5));
            Assert.Throws<ArgumentException>(() => ShL2.Blend(new[] { a, b }, new[] { 1.0 }));
        }

        [Test]
        public void IndexerFollowsUnityChannelMajorLayoutAndRejectsBadIndices()
        {
            var probe = new ShL2();
            probe[1, 4] = 3f;
            Assert.That(probe.ToArray()[13], Is.EqualTo(3f));
            Assert.Throws<ArgumentOutOfRangeException>(() => { var unused = probe[3, 0]; });
            Assert.Throws<ArgumentOutOfRangeException>(() => { var unused = probe[0, 9]; });
        }

        [Test]
        public void HdrCoefficientsFromTinyToHugeEvaluateWithFloatPrecision([Values(1e-6, 1.0, 1e6)] double scale)
        {
            var sh = RandomSh(7);
            var scaled = new float[27];
            for (int c = 0; c < 27; c++) scaled[c] = (float)(sh[c] * scale);
            var d = Vector3.Normalize(new Vector3(0.5f, 0.5f, -0.7f));
            var reference = ShMath.Evaluate(sh, 0, d);
            var value = ShMath.Evaluate(scaled, 0, d);
            Assert.That(value.X / scale, Is.EqualTo(reference.X).Within(1e-5 * (1 + Math.Abs(reference.X))));
        }

        [Test]
        public void LuminanceUsesRec709Weights()
        {
            Assert.That(ColorSpaces.Luminance(new Vector3(1, 0, 0)), Is.EqualTo(0.2126f).Within(1e-7));
            Assert.That(ColorSpaces.Luminance(new Vector3(0, 1, 0)), Is.EqualTo(0.7152f).Within(1e-7));
            Assert.That(ColorSpaces.Luminance(new Vector3(1, 1, 1)), Is.EqualTo(1f).Within(1e-6));
        }

        [Test]
        public void YCoCgRoundTripsAndMatchesTheDefinition()
        {
            var rgb = new Vector3(0.9f, 0.3f, 0.1f);
            var ycocg = ColorSpaces.RgbToYCoCg(rgb);
            Assert.That(ycocg.X, Is.EqualTo(0.9 / 4 + 0.3 / 2 + 0.1 / 4).Within(1e-6));
            Assert.That(ycocg.Y, Is.EqualTo(0.9 / 2 - 0.1 / 2).Within(1e-6));
            Assert.That(ycocg.Z, Is.EqualTo(-0.9 / 4 + 0.3 / 2 - 0.1 / 4).Within(1e-6));
            var back = ColorSpaces.YCoCgToRgb(ycocg);
            Assert.That(back.X, Is.EqualTo(rgb.X).Within(1e-6));
            Assert.That(back.Y, Is.EqualTo(rgb.Y).Within(1e-6));
            Assert.That(back.Z, Is.EqualTo(rgb.Z).Within(1e-6));
        }
    }
}
