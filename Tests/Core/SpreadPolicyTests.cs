using System;
using System.Linq;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Selection;
using Lpnn.Probes.Core.Tests.Support;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    /// <summary>The Spread policy in ProbeSelector: a prefix of the spread ranking, with the same corner and tetrahedron
    /// options as every other policy.</summary>
    [TestFixture]
    public class SpreadPolicyTests
    {
        private static float[] Scores(EvaluationGrid grid, int seed)
        {
            var random = new Random(seed);
            return Enumerable.Range(0, grid.Count).Select(_ => (float)random.NextDouble()).ToArray();
        }

        [Test]
        public void KeepsTheFirstKPointsOfTheSpreadRanking()
        {
            var grid = QualityFixtures.Box(6, 6, 6, 1);
            var scores = Scores(grid, 1);
            int[] order = SpreadRanking.Rank(grid, scores);
            foreach (int k in new[] { 4, 10, 50 })
            {
                var result = ProbeSelector.Select(grid, scores, SelectionSettings.Spread(k));
                Assert.That(result.Indices, Is.EqualTo(order.Take(k).OrderBy(i => i).ToArray()), "K = " + k);
                Assert.That(result.AddedForTetrahedron, Is.EqualTo(0));
            }
            Assert.That(ProbeSelector.Select(grid, scores, SelectionSettings.Spread(10000)).Indices.Length, Is.EqualTo(grid.Count));
            // Differs from top-K: spread keeps probes apart instead of clustering them on the best scores.
            Assert.That(ProbeSelector.Select(grid, scores, SelectionSettings.Spread(20)).Indices,
                Is.Not.EqualTo(ProbeSelector.Select(grid, scores, SelectionSettings.Budget(20)).Indices));
        }

        [TestCase(1)]
        [TestCase(2)]
        [TestCase(3)]
        public void FewerThanFourProbesAreCompletedToATetrahedron(int k)
        {
            var grid = QualityFixtures.Box(5, 4, 3, 1);
            var result = ProbeSelector.Select(grid, Scores(grid, 2), SelectionSettings.Spread(k));
            Assert.That(result.Indices.Length, Is.EqualTo(4));
            Assert.That(result.AddedForTetrahedron, Is.EqualTo(4 - k));
        }

        [Test]
        public void AllEqualAndNanScoresStillSpreadAndCornersCanBeKept()
        {
            var grid = QualityFixtures.Box(7, 5, 4, 1);
            var equal = Enumerable.Repeat(0.7f, grid.Count).ToArray();
            var nan = Enumerable.Repeat(float.NaN, grid.Count).ToArray();
            var a = ProbeSelector.Select(grid, equal, SelectionSettings.Spread(12));
            var b = ProbeSelector.Select(grid, nan, SelectionSettings.Spread(12));
            Assert.That(a.Indices, Is.EqualTo(b.Indices), "all-NaN scores are all-equal weights");
            var corners = ProbeSelector.Select(grid, equal, SelectionSettings.Spread(4, keepCorners: true));
            Assert.That(corners.Indices.Length, Is.EqualTo(8), "the 4 seeds are corners; the other 4 corners are added");
            Assert.That(corners.CornersAdded, Is.EqualTo(4));
        }

        [Test]
        public void AFlatGridIsRefusedAndBadBudgetsAreNamed()
        {
            var flat = GridBuilder.Build(new[] { GridBox.AxisAligned(Double3.Zero, new Double3(5, 5, 0)) }, 1);
            StringAssert.Contains("one plane", Assert.Throws<SelectionException>(() => ProbeSelector.Select(flat, Scores(flat, 3), SelectionSettings.Spread(10))).Message);
            StringAssert.Contains("probe budget 0 must be a whole number", Assert.Throws<SelectionException>(() => SelectionSettings.Spread(0).Validate()).Message);
            var fractional = new SelectionSettings { Policy = SelectionPolicy.Spread, Value = 2.5 };
            StringAssert.Contains("probe budget 2.5", Assert.Throws<SelectionException>(() => fractional.Validate()).Message);
        }

        [Test]
        public void ScoredPointsComputeEachRankingOnce()
        {
            var grid = QualityFixtures.Box(5, 5, 5, 1);
            var points = new ScoredPoints(grid, Scores(grid, 4));
            Assert.That(points.SpreadOrder, Is.SameAs(points.SpreadOrder));
            Assert.That(points.ScoreOrder, Is.SameAs(points.ScoreOrder));
            Assert.That(ProbeSelector.Select(points, SelectionSettings.Percentile(0.9), null).Indices,
                Is.EqualTo(ProbeSelector.Select(grid, points.Scores, SelectionSettings.Percentile(0.9)).Indices));
            StringAssert.Contains("got 3 scores for 125 points", Assert.Throws<SelectionException>(() => new ScoredPoints(grid, new float[3])).Message);
        }
    }
}
