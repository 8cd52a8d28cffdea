using Lpnn.Probes.Core.Placement;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    /// <summary>The one rule every heavy inspector button asks: time from the point count and the rates measured in
    /// Documentation~/benchmarks.md (§7.4, §11.3), a confirmation above 10 s or, without a measured rate, above 250,000 points.</summary>
    [TestFixture]
    public class HeavyOperationPolicyTests
    {
        [Test]
        public void RefinementAtAMillionPointsIsMinutesFromTheMeasuredRound()
        {
            // §11.3: one round 2.49 s at 10⁶ points; §11.2: up to 150 rounds on a whole level.
            var estimate = HeavyOperationPolicy.Estimate(1000000, new[] { HeavyOperation.BatchedRefinement });
            Assert.That(estimate.Seconds, Is.EqualTo(150 * 2.49).Within(1e-6));
            Assert.That(estimate.NeedsConfirmation, Is.True);
            StringAssert.Contains("about 7 min", estimate.Describe());
        }

        [TestCase(10000, false)]   // 3.7 s
        [TestCase(100000, true)]   // 37 s
        public void RefinementIsConfirmedAboveTenSeconds(long points, bool confirmed)
        {
            var estimate = HeavyOperationPolicy.Estimate(points, new[] { HeavyOperation.BatchedRefinement });
            Assert.That(estimate.NeedsConfirmation, Is.EqualTo(confirmed), "estimate " + estimate.Seconds + " s");
        }

        [Test]
        public void TheWholeRankingGrowsLinearlyFromTheMeasuredRound()
        {
            double atTenThousand = HeavyOperationPolicy.Estimate(10000, new[] { HeavyOperation.InsertionRanking }).Seconds;
            double atAMillion = HeavyOperationPolicy.Estimate(1000000, new[] { HeavyOperation.InsertionRanking }).Seconds;
            Assert.That(atAMillion, Is.EqualTo(100 * atTenThousand).Within(1e-9));
            // 11 rounds' worth of the 4.90 s round plus the reference lighting and typical tetrahedron (2.48 + 7.45 s).
            Assert.That(atAMillion, Is.EqualTo(11 * 4.90 + 2.48 + 7.45).Within(1e-6));
        }

        [TestCase(250000, false)]
        [TestCase(250001, true)]
        public void StepsWithoutAMeasuredRateFallBackToTheGridSize(long points, bool confirmed)
        {
            var estimate = HeavyOperationPolicy.Estimate(points, new[] { HeavyOperation.Lighting });
            Assert.That(estimate.NeedsConfirmation, Is.EqualTo(confirmed));
            Assert.That(estimate.Seconds, Is.EqualTo(0));
            Assert.That(estimate.FullyMeasured, Is.False);
            Assert.That(estimate.Describe(), Is.Empty);
        }

        [Test]
        public void OperationsAddUp()
        {
            var ops = new[] { HeavyOperation.InsertionRanking, HeavyOperation.ToleranceSearch, HeavyOperation.BatchedRefinement };
            double sum = 0;
            foreach (var op in ops) sum += HeavyOperationPolicy.Estimate(50000, new[] { op }).Seconds;
            Assert.That(HeavyOperationPolicy.Estimate(50000, ops).Seconds, Is.EqualTo(sum).Within(1e-9));
        }

        [Test]
        public void ApplyOfARefinedInsertionRunsRankingSearchAndRefinement()
        {
            Assert.That(HeavyOperationPolicy.PlacementOperations(true, true, true, false),
                Is.EqualTo(new[] { HeavyOperation.InsertionRanking, HeavyOperation.ToleranceSearch, HeavyOperation.BatchedRefinement }));
            Assert.That(HeavyOperationPolicy.PlacementOperations(true, true, true, true),
                Is.EqualTo(new[] { HeavyOperation.InsertionRanking, HeavyOperation.ToleranceSearch }));
            Assert.That(HeavyOperationPolicy.PlacementOperations(false, false, true, false), Is.Empty);
        }

        [Test]
        public void ANegativePointCountIsNamed()
        {
            var error = Assert.Throws<LpnnException>(() => HeavyOperationPolicy.Estimate(-5, new[] { HeavyOperation.Grid }));
            StringAssert.Contains("-5", error.Message);
        }
    }
}
