using Lpnn.Probes.Core.Features;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    [TestFixture]
    public class ProbeSampleCountsTests
    {
        [Test]
        public void UnityDefaultsGiveUnityProbeCounts()
        {
            // Unity's default Lighting Settings: 32 direct, 512 indirect, 256 environment samples, multiplier 4.
            var counts = ProbeSampleCounts.FromLightingSettings(32, 512, 256, 4f);
            Assert.That(counts.Direct, Is.EqualTo(128));
            Assert.That(counts.Indirect, Is.EqualTo(2048));
            Assert.That(counts.Validity, Is.EqualTo(2048));
        }

        [Test]
        public void EnvironmentSamplesRaiseTheIndirectCount()
        {
            var counts = ProbeSampleCounts.FromLightingSettings(10, 100, 300, 2f);
            Assert.That(counts.Indirect, Is.EqualTo(600));
            Assert.That(counts.Validity, Is.EqualTo(600));
            Assert.That(counts.Direct, Is.EqualTo(20));
        }

        [Test]
        public void MultiplierIsTruncatedLikeUnity()
        {
            Assert.That(ProbeSampleCounts.FromLightingSettings(10, 10, 10, 2.9f).Direct, Is.EqualTo(20));
        }

        [Test]
        public void ExtremesStayPositiveAndBounded()
        {
            var zero = ProbeSampleCounts.FromLightingSettings(0, -5, 0, 0f);
            Assert.That(zero.Direct, Is.EqualTo(1));
            Assert.That(zero.Indirect, Is.EqualTo(1));
            Assert.That(ProbeSampleCounts.FromLightingSettings(5, 5, 5, float.NaN).Direct, Is.EqualTo(5));
            var huge = ProbeSampleCounts.FromLightingSettings(int.MaxValue, int.MaxValue, 0, 1e9f);
            Assert.That(huge.Direct, Is.EqualTo(int.MaxValue));
            Assert.That(huge.Indirect, Is.EqualTo(int.MaxValue));
        }
    }
}
