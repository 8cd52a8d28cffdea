using System;
using System.Diagnostics;
using System.Linq;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Selection;
using Lpnn.Probes.Core.Tests.Support;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    /// <summary>The spread ranking (Documentation~/selection.md, "Spread ranking") against a plain O(N²) transcription of
    /// the text, on the cases that break fast implementations: ties everywhere, extreme weights, NaN, far coordinates.</summary>
    [TestFixture]
    public class SpreadRankingTests
    {
        private static float[] RandomScores(int count, int seed)
        {
            var random = new Random(seed);
            var scores = new float[count];
            for (int n = 0; n < count; n++) scores[n] = (float)random.NextDouble();
            return scores;
        }

        private static void AssertSameAsNaive(float[] positions, float[] scores, string what)
        {
            int[] expected = NaiveSpreadRanking.Rank(positions, scores);
            int[] actual = SpreadRanking.Rank(positions, scores, int.MaxValue);
            for (int r = 0; r < expected.Length; r++)
                if (expected[r] != actual[r])
                    Assert.Fail(what + ": rank " + r + " is point " + actual[r] + ", the plain algorithm says " + expected[r]);
            Assert.That(actual.Length, Is.EqualTo(expected.Length), what);
        }

        [Test]
        public void MatchesThePlainAlgorithmOnRandomScores()
        {
            var grid = QualityFixtures.Box(9, 7, 6, 0.5);
            AssertSameAsNaive(grid.CopyPositions(), RandomScores(grid.Count, 1), "random scores");
        }

        [Test]
        public void MatchesThePlainAlgorithmWhenEveryScoreIsEqual()
        {
            // Equal weights on a lattice: almost every step is a tie of exactly equal distances, decided by index.
            var grid = QualityFixtures.Box(8, 8, 5, 0.25);
            var scores = Enumerable.Repeat(0.5f, grid.Count).ToArray();
            AssertSameAsNaive(grid.CopyPositions(), scores, "equal scores");
        }

        [Test]
        public void MatchesThePlainAlgorithmWithExtremeNanAndInfiniteScores()
        {
            var grid = QualityFixtures.Box(10, 6, 5, 1);
            var scores = RandomScores(grid.Count, 2);
            for (int n = 0; n < scores.Length; n++)
            {
                if (n % 7 == 0) scores[n] = float.NaN;
                else if (n % 11 == 0) scores[n] = float.PositiveInfinity;
                else if (n % 13 == 0) scores[n] = float.NegativeInfinity;
                else if (n % 3 == 0) scores[n] = 1e-9f;
                else if (n % 5 == 0) scores[n] = 40f;
            }
            AssertSameAsNaive(grid.CopyPositions(), scores, "extreme scores");
        }

        [Test]
        public void MatchesThePlainAlgorithmWhenHalfTheVolumeHasNearZeroWeight()
        {
            // Weights 1000× apart keep a large distance alive until late: the case a single search radius handles badly.
            var grid = QualityFixtures.Box(12, 6, 4, 1);
            var scores = new float[grid.Count];
            for (int n = 0; n < grid.Count; n++) scores[n] = grid.GetId(n).I < 6 ? 1f : 1e-6f;
            AssertSameAsNaive(grid.CopyPositions(), scores, "two weight regions");
        }

        [Test]
        public void MatchesThePlainAlgorithmFarFromTheOriginAndOnScatteredPoints()
        {
            var far = QualityFixtures.Box(7, 6, 5, 0.5, new Double3(-40000, 25000, 12000.5));
            AssertSameAsNaive(far.CopyPositions(), RandomScores(far.Count, 3), "far from the origin");
            var random = new Random(4);
            var scattered = new float[3 * 300];
            for (int c = 0; c < scattered.Length; c++) scattered[c] = (float)(random.NextDouble() * 10 - 5);
            // Repeated positions (distance 0) must still appear once each, in index order among equals.
            Array.Copy(scattered, 0, scattered, 30, 30);
            AssertSameAsNaive(scattered, RandomScores(300, 5), "scattered points with duplicates");
        }

        [Test]
        public void StartsWithTheBoxCornersAndIsAPermutation()
        {
            var grid = QualityFixtures.Box(6, 5, 4, 1);
            int[] order = SpreadRanking.Rank(grid, RandomScores(grid.Count, 6));
            Assert.That(order.OrderBy(i => i).ToArray(), Is.EqualTo(Enumerable.Range(0, grid.Count).ToArray()));
            // On a box the D14 extremes are its 8 corners (the 6 axis directions pick corners too: lowest index among equals).
            var corners = order.Take(8).Select(i => grid.GetId(i)).ToArray();
            foreach (var id in corners)
            {
                Assert.That(id.I == 0 || id.I == 5, "corner x of " + id);
                Assert.That(id.J == 0 || id.J == 4, "corner y of " + id);
                Assert.That(id.K == 0 || id.K == 3, "corner z of " + id);
            }
            Assert.That(corners.Distinct().Count(), Is.EqualTo(8));
        }

        [Test]
        public void PrefixesEqualTheFullRankingAndScalingScoresChangesNothing()
        {
            var grid = QualityFixtures.Box(7, 7, 4, 1);
            var scores = RandomScores(grid.Count, 7).Select(s => 0.01f + 0.4f * s).ToArray();
            int[] full = SpreadRanking.Rank(grid, scores);
            foreach (int k in new[] { 0, 1, 3, 8, 14, 50, grid.Count, grid.Count + 10 })
                Assert.That(SpreadRanking.Rank(grid, scores, k), Is.EqualTo(full.Take(k).ToArray()), "prefix " + k);
            // Weights are relative to the median: doubling every score (exact in binary, no clipping) keeps the order.
            Assert.That(SpreadRanking.Rank(grid, scores.Select(s => 2 * s).ToArray()), Is.EqualTo(full));
        }

        [Test]
        public void NanScoresCountAsTheFloorAndWeightsFollowTheText()
        {
            var grid = QualityFixtures.Box(5, 5, 5, 1);
            var scores = RandomScores(grid.Count, 8);
            var withNan = (float[])scores.Clone();
            var withFloor = (float[])scores.Clone();
            for (int n = 0; n < scores.Length; n += 4)
            {
                withNan[n] = float.NaN;
                withFloor[n] = -3f;
            }
            Assert.That(SpreadRanking.Rank(grid, withNan), Is.EqualTo(SpreadRanking.Rank(grid, withFloor)));
            Assert.That(SpreadWeights.Compute(new[] { 0.25f, 1f, 4f, float.NaN }), Is.EqualTo(new[] { Math.Sqrt(0.25 / 0.625), Math.Sqrt(1 / 0.625), Math.Sqrt(1 / 0.625), Math.Sqrt(1e-6 / 0.625) }));
            Assert.That(SpreadWeights.Compute(new[] { 0.3f, 0.3f, 0.3f }), Is.EqualTo(new[] { 1.0, 1.0, 1.0 }));
            Assert.That(SpreadWeights.Compute(new float[0]), Is.Empty);
        }

        [Test]
        public void TinyInputsAndBadInputs()
        {
            Assert.That(SpreadRanking.Rank(new float[0], new float[0], 5), Is.Empty);
            Assert.That(SpreadRanking.Rank(new[] { 1f, 2f, 3f }, new[] { 0.5f }, 5), Is.EqualTo(new[] { 0 }));
            Assert.That(SpreadRanking.Rank(new[] { 0f, 0, 0, 1, 0, 0 }, new[] { 0.1f, 0.9f }, 5), Is.EqualTo(new[] { 1, 0 }));
            StringAssert.Contains("need one score per point", Assert.Throws<SelectionException>(() => SpreadRanking.Rank(new float[6], new float[3], 2)).Message);
            StringAssert.Contains("point 1 has a non-finite position", Assert.Throws<SelectionException>(
                () => SpreadRanking.Rank(new[] { 0f, 0, 0, float.NaN, 0, 0 }, new[] { 1f, 1f }, 2)).Message);
        }

        [Test]
        public void RanksAQuarterMillionPointsQuickly()
        {
            var grid = QualityFixtures.Box(64, 64, 64, 0.5);
            var scores = new float[grid.Count];
            for (int n = 0; n < grid.Count; n++)
            {
                var id = grid.GetId(n);
                // Weight contrast of 1000 and many exact ties: the hard case for the update radius.
                scores[n] = id.I < 20 ? 1e-6f : (id.J % 9 == 0 ? 1f : 0.05f);
            }
            var clock = Stopwatch.StartNew();
            int[] order = SpreadRanking.Rank(grid, scores);
            double seconds = clock.Elapsed.TotalSeconds;
            Assert.That(order.Length, Is.EqualTo(grid.Count));
            var seen = new bool[grid.Count];
            foreach (int i in order) seen[i] = true;
            Assert.That(seen.All(s => s), "every point ranked once");
            Assert.That(seconds, Is.LessThan(30), "262,144 points took " + InvariantFormat.Number(seconds) + " s");
            Console.WriteLine("spread ranking of " + grid.Count + " points: " + InvariantFormat.Number(Math.Round(seconds, 2)) + " s");
        }
    }
}
