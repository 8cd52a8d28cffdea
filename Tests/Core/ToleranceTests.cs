using System;
using System.Collections.Generic;
using System.Linq;
using System.Numerics;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Quality;
using Lpnn.Probes.Core.Selection;
using Lpnn.Probes.Core.Tests.Support;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    /// <summary>The tolerance policy (Documentation~/quality.md §4): the search's guarantees on synthetic error curves,
    /// and the whole policy on a lit grid with a real tetrahedraliser.</summary>
    [TestFixture]
    public class ToleranceTests
    {
        private EvaluationGrid _grid;
        private ReferenceLighting _reference;
        private float[] _scores;

        [TestFixtureSetUp]
        public void LightAGrid()
        {
            _grid = QualityFixtures.Box(8, 7, 5, 0.5);
            // The reference sees jittered positions, so the test Delaunay is unique; the grid keeps exact lattice ids for
            // the tetrahedron guarantee and the corners.
            var positions = QualityFixtures.Jittered(QualityFixtures.Positions(_grid), 0.03f, 51);
            _reference = ReferenceLighting.Create(positions, QualityFixtures.BlobField(positions, new Vector3(1, 1, 1), new Vector3(3, 2, 1.5f), 0.9f));
            var random = new Random(52);
            _scores = Enumerable.Range(0, _grid.Count).Select(_ => (float)random.NextDouble()).ToArray();
        }

        private static void AssertSearchGuarantees(ToleranceSearchResult result, double tolerance, int pointCount)
        {
            var evaluated = result.Evaluated.ToDictionary(e => e.Key, e => e.Value);
            Assert.That(evaluated[result.Count], Is.LessThanOrEqualTo(tolerance));
            Assert.That(result.MeanError, Is.EqualTo(evaluated[result.Count]));
            if (result.Count > Math.Min(ToleranceSearch.SmallestCount, pointCount))
            {
                int window = Math.Max(1, result.Count / ToleranceSearch.Resolution);
                Assert.That(result.Evaluated.Any(e => e.Key < result.Count && e.Key >= result.Count - window && e.Value > tolerance),
                            "a count within max(1, count / Resolution) below the answer was evaluated and failed");
            }
            foreach (var e in result.Evaluated.Where(e => e.Key < result.Count))
                Assert.That(e.Value, Is.GreaterThan(tolerance), "evaluated count " + e.Key + " below the answer failed");
            Assert.That(result.Evaluated.Count, Is.LessThanOrEqualTo(2 * Math.Log(pointCount, 2) + 2));
            Assert.That(result.Evaluated.Select(e => e.Key).ToArray(), Is.Ordered);
        }

        [Test]
        public void TheSearchGuaranteesWhatItChecksOnANonMonotonicCurve()
        {
            // Falls like 1/k but with bumps: k = 37 passes, 38..40 fail again.
            Func<int, double> curve = k => (k >= 38 && k <= 40 ? 0.5 : 1.0 / k);
            var calls = new List<int>();
            var result = ToleranceSearch.Run(1000, k => { calls.Add(k); return curve(k); }, 1.0 / 37);
            AssertSearchGuarantees(result, 1.0 / 37, 1000);
            Assert.That(calls.Take(5).ToArray(), Is.EqualTo(new[] { 4, 8, 16, 32, 64 }), "exponential from 4");
            Assert.That(calls.Distinct().Count(), Is.EqualTo(calls.Count), "no count is evaluated twice");
            Assert.That(result.Count, Is.EqualTo(37).Or.EqualTo(41), "a count whose neighbour below failed");
        }

        [Test]
        public void AboveTheResolutionTheSearchStopsAtAFractionOfTheCountAndSavesEvaluations()
        {
            // A smooth falling curve with its smallest passing count at 7,779 of 10^6 points (as the 10^6-point level of
            // benchmarks.md "Scale: whole levels"): bisection to the unit needs 12 halvings after 4, 8, …, 8192 (24 evaluations); stopping
            // once the bracket is at most count / 256 apart takes 8 (20 evaluations), at the price of at most ~30 probes.
            const int trueAnswer = 7779;
            Func<int, double> curve = k => 0.05 * Math.Sqrt((double)trueAnswer / k);
            var result = ToleranceSearch.Run(1000000, curve, 0.05);
            AssertSearchGuarantees(result, 0.05, 1000000);
            Assert.That(result.Count, Is.InRange(trueAnswer, trueAnswer + trueAnswer / ToleranceSearch.Resolution));
            Assert.That(result.Count, Is.EqualTo(7792), "the same answer as Python's search (test_quality_policies.py)");
            int unitSearch = 12 + 12; // 4 … 8192 (12 counts), then 12 halvings of the 4,096 between 4,096 and 8,192
            Assert.That(result.Evaluated.Count, Is.EqualTo(unitSearch - 4));
            Assert.That(ToleranceSearch.Resolved(4096, 8192), Is.False);
            Assert.That(ToleranceSearch.Resolved(7776, 7806), Is.True, "30 × 256 ≤ 7,806");
            Assert.That(ToleranceSearch.Resolved(7776, 7807), Is.False, "31 × 256 > 7,807");
            Assert.That(ToleranceSearch.Resolved(200, 201), Is.True, "adjacent");
            Assert.That(ToleranceSearch.Resolved(199, 201), Is.False, "below 256 the search goes to the unit");
            Assert.That(ToleranceSearch.Resolved(int.MaxValue - 100000000, int.MaxValue), Is.False, "no overflow (10^8 × 256 exceeds an int)");
        }

        [Test]
        public void TheSearchHandlesTinyGridsAndEdgeCurves()
        {
            Assert.That(ToleranceSearch.Run(3, k => k == 3 ? 0 : 1, 0.1).Count, Is.EqualTo(3));
            Assert.That(ToleranceSearch.Run(1, k => 0, 0.1).Count, Is.EqualTo(1));
            Assert.That(ToleranceSearch.Run(100, k => 0.01, 0.02).Count, Is.EqualTo(4), "4 already passes");
            var last = ToleranceSearch.Run(100, k => k == 100 ? 0 : 1, 0.5);
            Assert.That(last.Count, Is.EqualTo(100));
            AssertSearchGuarantees(last, 0.5, 100);
            StringAssert.Contains("even all 100 points miss the tolerance", Assert.Throws<SelectionException>(() => ToleranceSearch.Run(100, k => 1, 0.5)).Message);
            StringAssert.Contains("must be a mean error greater than 0", Assert.Throws<SelectionException>(() => ToleranceSearch.Run(100, k => 0, 0)).Message);
            Assert.Throws<SelectionException>(() => ToleranceSearch.Run(100, k => 0, double.NaN));
            StringAssert.Contains("not a number", Assert.Throws<SelectionException>(() => ToleranceSearch.Run(100, k => double.NaN, 0.1)).Message);
        }

        [Test]
        public void ThePolicyReturnsTheSmallestCheckedSpreadPrefixWithinTolerance()
        {
            var delaunay = new BowyerWatsonDelaunay();
            const double tolerance = 0.01;
            var result = TolerancePolicy.Place(_grid, _scores, _reference, delaunay, tolerance);
            Assert.That(result.Tolerance, Is.Not.Null);
            AssertSearchGuarantees(result.Tolerance, tolerance, _grid.Count);
            Assert.That(result.Tolerance.Count, Is.GreaterThan(8).And.LessThan(_grid.Count), "a real search, not an end point");
            // The set is exactly the spread policy's at that count, and its error is what the search recorded.
            var spread = ProbeSelector.Select(_grid, _scores, SelectionSettings.Spread(result.Tolerance.Count));
            Assert.That(result.Indices, Is.EqualTo(spread.Indices));
            double error = new PlacementEvaluator(_reference, delaunay).MeanError(result.Indices);
            Assert.That(error, Is.EqualTo(result.Tolerance.MeanError));
            Assert.That(error, Is.LessThanOrEqualTo(tolerance));
            // The same through ProbeSelector with the Tolerance settings.
            var selected = ProbeSelector.Select(new ScoredPoints(_grid, _scores), SelectionSettings.Tolerance(tolerance), new PlacementEvaluator(_reference, delaunay));
            Assert.That(selected.Indices, Is.EqualTo(result.Indices));
        }

        [Test]
        public void ALooseToleranceKeepsFourProbesAndCornersAreMeasuredToo()
        {
            var delaunay = new BowyerWatsonDelaunay();
            var loose = TolerancePolicy.Place(_grid, _scores, _reference, delaunay, 0.99);
            Assert.That(loose.Indices.Length, Is.EqualTo(4));
            Assert.That(loose.Tolerance.Evaluated.Count, Is.EqualTo(1));

            var withCorners = TolerancePolicy.Place(_grid, _scores, _reference, delaunay, 0.02, keepBoundsCorners: true);
            Assert.That(withCorners.Indices.Length, Is.GreaterThanOrEqualTo(8));
            foreach (var corner in new[] { 0, 7, 48, 55, 224, 231, 272, 279 })
                Assert.That(withCorners.Indices, Contains.Item(corner), "box corner " + corner);
            Assert.That(new PlacementEvaluator(_reference, delaunay).MeanError(withCorners.Indices), Is.LessThanOrEqualTo(0.02));
            AssertSearchGuarantees(withCorners.Tolerance, 0.02, _grid.Count);
        }

        [Test]
        public void AnyRankingCanBeSearched()
        {
            var delaunay = new BowyerWatsonDelaunay();
            int[] byScore = ScoreRanking.Rank(_scores);
            var result = TolerancePolicy.Place(_grid, byScore, _reference, delaunay, 0.02);
            AssertSearchGuarantees(result.Tolerance, 0.02, _grid.Count);
            var prefix = new HashSet<int>(byScore.Take(result.Tolerance.Count));
            Assert.That(prefix.IsSubsetOf(result.Indices), "the answer holds the ranking's prefix");
            StringAssert.Contains("lists point 3 twice", Assert.Throws<SelectionException>(
                () => TolerancePolicy.Place(_grid, byScore.Select(i => i == 4 ? 3 : i).ToArray(), _reference, delaunay, 0.02)).Message);
        }

        [Test]
        public void ToleranceWithoutLightingExplainsWhatIsMissing()
        {
            var error = Assert.Throws<SelectionException>(() => ProbeSelector.Select(_grid, _scores, SelectionSettings.Tolerance(0.02)));
            StringAssert.Contains("tolerance policy measures the placement error", error.Message);
            StringAssert.Contains("tolerance 0 must be a mean placement error greater than 0",
                Assert.Throws<SelectionException>(() => SelectionSettings.Tolerance(0).Validate()).Message);
            Assert.Throws<SelectionException>(() => SelectionSettings.Tolerance(double.PositiveInfinity).Validate());
            Assert.Throws<SelectionException>(() => SelectionSettings.Tolerance(double.NaN).Validate());
            StringAssert.Contains("grid has 280", Assert.Throws<PlacementErrorException>(() =>
                TolerancePolicy.Place(QualityFixtures.Box(8, 7, 5, 0.5), _scores, ReferenceLighting.Create(new[] { Vector3.Zero, Vector3.One }, new float[54]),
                    new BowyerWatsonDelaunay(), 0.02)).Message);
        }
    }
}
