using Lpnn.Probes.Core.Placement;
using Lpnn.Probes.Core.Selection;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    /// <summary>The one rule every heavy inspector button asks: time from the point count and the rates measured in
    /// Documentation~/benchmarks.md ("The C# core under Mono"), a confirmation above 10 s or, without a measured rate, above 250,000 points,
    /// and the placement panel's line of Apply's expected time.</summary>
    [TestFixture]
    public class HeavyOperationPolicyTests
    {
        [Test]
        public void ApplysStagesGoThroughTheTwoMeasuredLevels()
        {
            // benchmarks.md "The C# core under Mono", the Apply rehearsal on ctf_compromise (136,512 points) and at 0.8128 m (1,151,667): first stage + insertion
            // rounds 0.5 + 3.8 and 4.2 + 29.3 s, tolerance search 2.5 and 11.3 s, refinement 8.4 and 44.9 s (2026-11-29, medians of three runs).
            var cases = new[]
            {
                new { Op = HeavyOperation.InsertionRounds, Small = 4.3, Large = 33.5 },
                new { Op = HeavyOperation.ToleranceSearch, Small = 2.5, Large = 11.3 },
                new { Op = HeavyOperation.BatchedRefinement, Small = 8.4, Large = 44.9 },
            };
            foreach (var c in cases)
            {
                Assert.That(HeavyOperationPolicy.Estimate(136512, new[] { c.Op }).Seconds, Is.EqualTo(c.Small).Within(1e-9), c.Op.ToString());
                Assert.That(HeavyOperationPolicy.Estimate(1151667, new[] { c.Op }).Seconds, Is.EqualTo(c.Large).Within(1e-9), c.Op.ToString());
            }
        }

        [Test]
        public void TheWholeDefaultApplyAtTheMeasuredLevelsIsItsMeasuredTotal()
        {
            var apply = HeavyOperationPolicy.PlacementOperations(PlacementMethod.InsertionRefined, true, false, false);
            // benchmarks.md "The C# core under Mono" totals: 15.5 s and 90.0 s (the medians of the runs' totals, not of their stages).
            Assert.That(HeavyOperationPolicy.Estimate(136512, apply).Seconds, Is.EqualTo(4.3 + 2.5 + 8.4).Within(1e-9));
            Assert.That(HeavyOperationPolicy.Estimate(1151667, apply).Seconds, Is.EqualTo(33.5 + 11.3 + 44.9).Within(1e-9));
            StringAssert.StartsWith("about 90 s", HeavyOperationPolicy.Estimate(1151667, apply).Describe());
        }

        [Test]
        public void TheLeakAwareRefinementGoesThroughItsMeasuredLevels()
        {
            // benchmarks.md "The C# core under Mono", "The leak-aware Apply": the leak repair of the seed plus the refinement on
            // q3dm6ish, fan, oa_koth1, ctf_compromise and ctf_compromise at 0.8128 m (2026-11-29, two idle cores, medians of three runs).
            var measured = new[]
            {
                new { Points = 2100L, Seconds = 0.1 + 1.3 }, new { Points = 6940L, Seconds = 0.3 + 3.7 }, new { Points = 41931L, Seconds = 0.8 + 10.0 },
                new { Points = 136512L, Seconds = 2.4 + 26.4 }, new { Points = 1151667L, Seconds = 17.5 + 190.9 },
            };
            foreach (var m in measured)
                Assert.That(Leaky(m.Points), Is.EqualTo(m.Seconds).Within(1e-9), m.Points + " points");
            Assert.That(Leaky(1050), Is.EqualTo(1.4 / 2).Within(1e-9), "in proportion below the smallest level");
            Assert.That(Leaky((136512 + 1151667) / 2), Is.EqualTo((28.8 + 208.4) / 2).Within(1e-3), "linear between two levels");
            Assert.That(Leaky(2166822), Is.EqualTo(208.4 + (208.4 - 28.8)).Within(1e-6), "along the last segment beyond the largest");
            Assert.That(HeavyOperationPolicy.SecondsPerPoint(HeavyOperation.LeakAwareRefinement),
                Is.EqualTo((208.4 - 28.8) / (1151667 - 136512)).Within(1e-15));
        }

        private static double Leaky(long points) => HeavyOperationPolicy.Estimate(points, new[] { HeavyOperation.LeakAwareRefinement }).Seconds;

        [Test]
        public void AVolumeThatAvoidsLeaksIsPricedWithTheLeakAwareRefinement()
        {
            var avoiding = HeavyOperationPolicy.PlacementOperations(PlacementMethod.InsertionRefined, true, false, true);
            Assert.That(avoiding, Is.EqualTo(new[] { HeavyOperation.InsertionRounds, HeavyOperation.ToleranceSearch, HeavyOperation.LeakAwareRefinement }));
            var blind = HeavyOperationPolicy.PlacementOperations(PlacementMethod.InsertionRefined, true, false, false);
            // The same rounds and search as the leak-blind Apply (4.3 + 2.5 s at 136,512 points), the refinement as measured
            // leak-aware: 35.6 s, not the leak-blind 15.2 s.
            Assert.That(HeavyOperationPolicy.Estimate(136512, avoiding).Seconds, Is.EqualTo(4.3 + 2.5 + 28.8).Within(1e-9));
            Assert.That(HeavyOperationPolicy.Estimate(136512, avoiding).Seconds, Is.GreaterThan(2 * HeavyOperationPolicy.Estimate(136512, blind).Seconds));
            Assert.That(HeavyOperationPolicy.Estimate(1151667, avoiding).Seconds, Is.EqualTo(33.5 + 11.3 + 208.4).Within(1e-9));
            StringAssert.StartsWith("about 4 min", HeavyOperationPolicy.Estimate(1151667, avoiding).Describe());
            // A small volume stays small (q3dm6ish, 2,100 points: the leak-aware Apply measured 2.6 s), unconfirmed.
            var small = HeavyOperationPolicy.Estimate(2100, avoiding);
            Assert.That(small.Seconds, Is.InRange(2.0, 4.0));
            Assert.That(small.NeedsConfirmation, Is.False);
            // Leaks change only the refinement: Find probes (the search alone) and the unrefined methods cost the same.
            Assert.That(HeavyOperationPolicy.PlacementOperations(PlacementMethod.InsertionRefined, true, true, true),
                Is.EqualTo(HeavyOperationPolicy.PlacementOperations(PlacementMethod.InsertionRefined, true, true, false)));
            Assert.That(HeavyOperationPolicy.PlacementOperations(PlacementMethod.Insertion, true, false, true),
                Is.EqualTo(new[] { HeavyOperation.InsertionRounds, HeavyOperation.ToleranceSearch }));
        }

        [Test]
        public void TheApplyLineOfAVolumeThatAvoidsLeaksSaysSo()
        {
            string line = HeavyOperationPolicy.ApplyLine(136512, PlacementMethod.InsertionRefined, SelectionPolicy.Tolerance, false, false, true);
            Assert.That(line, Is.EqualTo("Apply: about 35 s for 136,512 points (insertion rounds, the tolerance search and the refinement in batches " +
                                         "avoiding light leaks; C# rates measured under Mono on real levels, Python's Qhull standing in for Unity's " +
                                         "tetrahedraliser and a C# ray hierarchy for Unity's physics, Documentation~/benchmarks.md \"The C# core under Mono\")."));
            // A method without the refinement has nothing for the leaks to change.
            Assert.That(HeavyOperationPolicy.ApplyLine(136512, PlacementMethod.Network, SelectionPolicy.Tolerance, false, false, true),
                Is.EqualTo(HeavyOperationPolicy.ApplyLine(136512, PlacementMethod.Network, SelectionPolicy.Tolerance, false, false, false)));
        }

        [Test]
        public void RefinementAtAMillionPointsFollowsTheLineThroughItsTwoLevels()
        {
            var estimate = HeavyOperationPolicy.Estimate(1000000, new[] { HeavyOperation.BatchedRefinement });
            Assert.That(estimate.Seconds, Is.EqualTo(8.4 + (44.9 - 8.4) / (1151667 - 136512) * (1000000 - 136512)).Within(1e-9));
            Assert.That(estimate.NeedsConfirmation, Is.True);
            StringAssert.StartsWith("about 40 s at the rates measured under Mono", estimate.Describe());
            StringAssert.DoesNotContain("tetrahedralisations", estimate.Describe());
        }

        [TestCase(1000, false)]    // 3.5 s: the refinement's rounds cost even on a small volume
        [TestCase(200000, true)]   // 10.7 s
        public void RefinementIsConfirmedAboveTenSeconds(long points, bool confirmed)
        {
            var estimate = HeavyOperationPolicy.Estimate(points, new[] { HeavyOperation.BatchedRefinement });
            Assert.That(estimate.NeedsConfirmation, Is.EqualTo(confirmed), "estimate " + estimate.Seconds + " s");
        }

        [Test]
        public void AnEmptyGridCostsNothing()
        {
            var estimate = HeavyOperationPolicy.Estimate(0, HeavyOperationPolicy.PlacementOperations(PlacementMethod.InsertionRefined, true, false, false));
            Assert.That(estimate.Seconds, Is.EqualTo(0));
            Assert.That(estimate.NeedsConfirmation, Is.False);
        }

        [Test]
        public void TheWholeRankingGrowsLinearlyFromTheMeasuredRound()
        {
            double atTenThousand = HeavyOperationPolicy.Estimate(10000, new[] { HeavyOperation.InsertionRanking }).Seconds;
            double atAMillion = HeavyOperationPolicy.Estimate(1000000, new[] { HeavyOperation.InsertionRanking }).Seconds;
            Assert.That(atAMillion, Is.EqualTo(100 * atTenThousand).Within(1e-9));
            // 11 rounds' worth of the 4.90 s round plus the reference lighting and typical tetrahedron (2.48 + 7.45 s).
            Assert.That(atAMillion, Is.EqualTo(11 * 4.90 + 2.48 + 7.45).Within(1e-6));
            // Its rate leaves Unity's tetrahedralisations out, and says so.
            StringAssert.EndsWith("plus Unity's tetrahedralisations",
                HeavyOperationPolicy.Estimate(1000000, new[] { HeavyOperation.InsertionRanking }).Describe());
        }

        [TestCase(250000, false)]
        [TestCase(250001, true)]
        public void StepsWithoutAMeasuredRateFallBackToTheGridSize(long points, bool confirmed)
        {
            var estimate = HeavyOperationPolicy.Estimate(points, new[] { HeavyOperation.Lighting });
            Assert.That(HeavyOperationPolicy.FixedSeconds(HeavyOperation.Lighting), Is.EqualTo(0));
            Assert.That(estimate.NeedsConfirmation, Is.EqualTo(confirmed));
            Assert.That(estimate.Seconds, Is.EqualTo(0));
            Assert.That(estimate.FullyMeasured, Is.False);
            Assert.That(estimate.Describe(), Is.Empty);
        }

        [Test]
        public void OperationsAddUp()
        {
            var ops = new[] { HeavyOperation.InsertionRounds, HeavyOperation.ToleranceSearch, HeavyOperation.BatchedRefinement };
            double sum = 0;
            foreach (var op in ops) sum += HeavyOperationPolicy.Estimate(50000, new[] { op }).Seconds;
            Assert.That(HeavyOperationPolicy.Estimate(50000, ops).Seconds, Is.EqualTo(sum).Within(1e-9));
        }

        [Test]
        public void ApplyOfARefinedInsertionRunsRoundsSearchAndRefinement()
        {
            Assert.That(HeavyOperationPolicy.PlacementOperations(PlacementMethod.InsertionRefined, true, false, false),
                Is.EqualTo(new[] { HeavyOperation.InsertionRounds, HeavyOperation.ToleranceSearch, HeavyOperation.BatchedRefinement }));
            Assert.That(HeavyOperationPolicy.PlacementOperations(PlacementMethod.InsertionRefined, true, true, false),
                Is.EqualTo(new[] { HeavyOperation.InsertionRounds, HeavyOperation.ToleranceSearch }));
            Assert.That(HeavyOperationPolicy.PlacementOperations(PlacementMethod.InsertionRefined, true, false, false, rankingKnown: true),
                Is.EqualTo(new[] { HeavyOperation.ToleranceSearch, HeavyOperation.BatchedRefinement }));
            Assert.That(HeavyOperationPolicy.PlacementOperations(PlacementMethod.Network, false, false, false), Is.Empty);
        }

        [TestCase(0.2, "under a second")]
        [TestCase(1.0, "about 1 s")]
        [TestCase(6.1, "about 7 s")]
        [TestCase(10.0, "about 10 s")]
        [TestCase(34.3, "about 35 s")]
        [TestCase(37.4, "about 35 s")]
        [TestCase(37.5, "about 40 s")]
        [TestCase(89.9, "about 90 s")]
        [TestCase(90.0, "about 2 min")]
        [TestCase(215.8, "about 4 min")]
        [TestCase(5399, "about 90 min")]
        [TestCase(5400, "about 1.5 h")]
        public void TimesAreRoundedToWhatAReaderNeeds(double seconds, string text)
        {
            Assert.That(HeavyOperationPolicy.ApproximateTime(seconds), Is.EqualTo(text));
        }

        [Test]
        public void TheApplyLineOfTheDefaultNamesItsTimeStepsAndSource()
        {
            string line = HeavyOperationPolicy.ApplyLine(136512, PlacementMethod.InsertionRefined, SelectionPolicy.Tolerance, false, false, false);
            Assert.That(line, Is.EqualTo("Apply: about 15 s for 136,512 points (insertion rounds, the tolerance search and the refinement in batches; " +
                                         "C# rates measured under Mono on real levels, Python's Qhull standing in for Unity's tetrahedraliser, " +
                                         "Documentation~/benchmarks.md \"The C# core under Mono\")."));
        }

        [Test]
        public void TheApplyLineSaysWhatItCannotKnow()
        {
            StringAssert.Contains("once the grid is built",
                HeavyOperationPolicy.ApplyLine(0, PlacementMethod.InsertionRefined, SelectionPolicy.Tolerance, false, false, false));
            StringAssert.StartsWith("Apply: under a second for 1,272 points",
                HeavyOperationPolicy.ApplyLine(1272, PlacementMethod.Insertion, SelectionPolicy.Budget, true, true, false));
            StringAssert.Contains("ranks the stored scores",
                HeavyOperationPolicy.ApplyLine(5000, PlacementMethod.Network, SelectionPolicy.Spread, false, false, false));
            string budget = HeavyOperationPolicy.ApplyLine(50000, PlacementMethod.GuidedInsertionRefined, SelectionPolicy.Budget, false, false, false);
            StringAssert.Contains("(guided insertion rounds and the refinement in batches;", budget);
            StringAssert.Contains("a budget of many probes takes more rounds", budget);
            StringAssert.Contains("guided rounds priced as plain insertion's", budget);
            string huge = HeavyOperationPolicy.ApplyLine(3000000, PlacementMethod.InsertionRefined, SelectionPolicy.Tolerance, false, false, false);
            StringAssert.Contains("extrapolated beyond the 1,151,667 points measured", huge);
            StringAssert.StartsWith("Apply: about 4 min for 3,000,000 points", huge);
        }

        [Test]
        public void TheNetworksToleranceSearchIsItsOnlyHeavyStep()
        {
            string line = HeavyOperationPolicy.ApplyLine(136512, PlacementMethod.Network, SelectionPolicy.Tolerance, false, false, false);
            StringAssert.StartsWith("Apply: about 3 s for 136,512 points (the tolerance search;", line);
        }

        [Test]
        public void ANegativePointCountIsNamed()
        {
            var error = Assert.Throws<LpnnException>(() => HeavyOperationPolicy.Estimate(-5, new[] { HeavyOperation.Grid }));
            StringAssert.Contains("-5", error.Message);
        }
    }
}
