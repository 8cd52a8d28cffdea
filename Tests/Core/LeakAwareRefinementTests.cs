using System;
using System.Linq;
using System.Numerics;
using System.Threading;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Json;
using Lpnn.Probes.Core.Pipeline;
using Lpnn.Probes.Core.Quality;
using Lpnn.Probes.Core.Selection;
using Lpnn.Probes.Core.Tests.Support;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    /// <summary>The leak-aware option of refined insertion (Documentation~/leaks.md "A leak-aware default"): parity with the
    /// Python reference through Tests/Data/leak_aware_golden.json (a walled room: the repaired seed, the answer at a budget
    /// and at τ), and its behaviour: off changes nothing, on leaks less within τ, a bad weight is refused, a cancel is
    /// honoured between repair rounds.</summary>
    [TestFixture]
    public class LeakAwareRefinementTests
    {
        private static int[] Ints(JsonValue array) => array.Items.Select(v => (int)v.AsNumber).ToArray();

        /// <summary>The golden walled room: its grid, lighting, wall and the insertion order the seeds come from.</summary>
        private sealed class WalledRoom
        {
            public JsonValue Golden;
            public EvaluationGrid Grid;
            public PlacementEvaluator Evaluator;
            public AnalyticBoxRaycaster Wall = new AnalyticBoxRaycaster();
            public InsertionOrder Order;

            public WalledRoom()
            {
                Golden = TestData.ReadJson("leak_aware_golden.json");
                Grid = GoldenLighting.Grid(Golden);
                Evaluator = new PlacementEvaluator(GoldenLighting.Reference(Golden, Grid), new BowyerWatsonDelaunay());
                foreach (var box in Golden.Get("obstacles").Items)
                    Wall.Boxes.Add(new AxisBox(AnalyticScene.ToDouble3(box.Get("min")), AnalyticScene.ToDouble3(box.Get("max"))));
                Order = new InsertionOrder(Grid, Evaluator.Reference, Evaluator.Tetrahedralizer);
            }

            public SelectionResult Place(SelectionSettings settings, LeakWeighting leaks)
            {
                var selection = ProbeSelector.SelectFromPrefixes(Grid, Order.Count, k => Order.Prefix(k), settings, Evaluator);
                return RefinedSelection.Refine(Grid, selection, k => Order.Prefix(k), Order.Count, settings, Evaluator, leaks);
            }

            public int Leaking(int[] probes)
            {
                var positions = probes.Select(p => Evaluator.Reference.GetPosition(p)).ToArray();
                return LeakCheck.Find(Evaluator.Reference, probes, Evaluator.Tetrahedralizer.Tetrahedralize(positions), Wall).Count(x => x);
            }
        }

        private static WalledRoom room;

        private static WalledRoom Room => room ?? (room = new WalledRoom());

        // ---- parity ---------------------------------------------------------------------------------------------------

        [Test]
        public void TheConstantsAreThePythonReferences()
        {
            Assert.That(Room.Golden.Get("leak_weight").AsNumber, Is.EqualTo(LeakWeighting.DefaultWeight));
            Assert.That((int)Room.Golden.Get("repair_rounds").AsNumber, Is.EqualTo(LeakRepair.DefaultRounds));
            StringAssert.StartsWith("exact", Room.Golden.Get("tolerance").AsString);
        }

        [Test]
        public void TheSeedAndItsRepairAreThePythonReferences()
        {
            var budget = Room.Golden.Get("budget");
            int count = (int)budget.Get("count").AsNumber;
            int[] seed = Room.Order.Prefix(RefinedSelection.BudgetSeedCount(count, Room.Order.Count)).Take(RefinedSelection.BudgetSeedCount(count, Room.Order.Count))
                .OrderBy(p => p).ToArray();
            Assert.That(seed, Is.EqualTo(Ints(budget.Get("seed"))), "the insertion order's prefix");
            var repaired = LeakRepair.Repaired(Room.Evaluator.Reference, Room.Evaluator.Tetrahedralizer, seed, Room.Wall);
            Assert.That(repaired, Is.EqualTo(Ints(budget.Get("repaired_seed"))));
            Assert.That(repaired.Length, Is.GreaterThan(seed.Length), "the seed leaks: the repair must add probes");
        }

        /// <summary>The room nearly black: every leaking point's error lies below InsertionRanking.Tie (yet they differ), and a
        /// repair round takes in each tetrahedron the lowest-index leaking point within Tie of the largest error (leaks.md "A
        /// leak-aware default" 1). Compared exactly, the largest error won, and on oa_koth1, where errors of round-off only
        /// differ in their last bits, C# and Python took different probes (quality.md §5.1).</summary>
        [Test]
        public void InADarkRoomTheRepairTakesTheLowestIndexAmongErrorsWithinTieAsThePythonReferenceDoes()
        {
            var c = Room.Golden.Get("dark_room_case");
            var reference = GoldenLighting.Reference(c, Room.Grid);
            int[] seed = Ints(c.Get("seed"));
            Assert.That(seed, Is.EqualTo(Ints(Room.Golden.Get("budget").Get("seed"))));
            var repaired = LeakRepair.Repaired(reference, Room.Evaluator.Tetrahedralizer, seed, Room.Wall);
            Assert.That(repaired, Is.EqualTo(Ints(c.Get("repaired_seed"))));
            Assert.That(repaired.Length, Is.GreaterThan(seed.Length), "the seed leaks: the repair must add probes");
        }

        [Test]
        public void ABudgetKeepsThePythonReferencesProbes()
        {
            var budget = Room.Golden.Get("budget");
            var placed = Room.Place(SelectionSettings.Budget((int)budget.Get("count").AsNumber), new LeakWeighting(Room.Wall));
            Assert.That(placed.Indices, Is.EqualTo(Ints(budget.Get("indices"))));
            Assert.That(placed.RefinedFrom, Is.EqualTo(budget.Get("repaired_seed").Items.Count));
            double error = budget.Get("mean_error").AsNumber;
            Assert.That(Room.Evaluator.MeanError(placed.Indices), Is.EqualTo(error).Within(1e-9 * error), "the plain metric's error");
        }

        [Test]
        public void AToleranceKeepsThePythonReferencesProbes()
        {
            var c = Room.Golden.Get("tolerance_case");
            double tau = c.Get("tolerance").AsNumber;
            var placed = Room.Place(SelectionSettings.Tolerance(tau), new LeakWeighting(Room.Wall));
            Assert.That(placed.Indices, Is.EqualTo(Ints(c.Get("indices"))));
            double error = c.Get("mean_error").AsNumber;
            Assert.That(Room.Evaluator.MeanError(placed.Indices), Is.EqualTo(error).Within(1e-9 * error));
            var plain = Room.Place(SelectionSettings.Tolerance(tau), null);
            Assert.That(plain.Indices, Is.EqualTo(Ints(c.Get("without_leaks"))), "the option off: today's answer");
        }

        /// <summary>The golden's pinned case: its pins snapped with its keep distance, and the insertion order that starts from them.</summary>
        private static Pins PinnedCase(JsonValue c, out InsertionOrder order)
        {
            var positions = c.Get("positions").Items.Select(AnalyticScene.ToDouble3).ToArray();
            var pins = Pins.Snap(Room.Grid, positions, c.Get("keep_distance").AsNumber);
            var sh = Room.Golden.Get("sh").Items.SelectMany(JsonArrays.Floats).ToArray();
            order = InsertionOrder.OfValid(Room.Grid, sh, Room.Evaluator.Reference.SceneScale, null, Room.Evaluator.Tetrahedralizer, pins);
            return pins;
        }

        [Test]
        public void WithPinsTheRepairLeavesTheLeaksNearThemToThePinsAsThePythonReferenceDoes()
        {
            var c = Room.Golden.Get("pinned_case");
            var pins = PinnedCase(c, out var order);
            Assert.That(pins.Indices, Is.EqualTo(Ints(c.Get("pins"))));
            Assert.That(Enumerable.Range(0, pins.Blocked.Length).Where(p => pins.Blocked[p]).ToArray(), Is.EqualTo(Ints(c.Get("blocked"))));
            int count = (int)Room.Golden.Get("budget").Get("count").AsNumber;
            int seedCount = RefinedSelection.BudgetSeedCount(count, order.Count);
            int[] seed = order.Prefix(seedCount).Take(seedCount).OrderBy(p => p).ToArray();
            Assert.That(seed, Is.EqualTo(Ints(c.Get("seed"))), "the pinned insertion order's prefix");
            var repaired = LeakRepair.Repaired(Room.Evaluator.Reference, Room.Evaluator.Tetrahedralizer, seed, Room.Wall, LeakRepair.DefaultRounds,
                CancellationToken.None, pins.Blocked);
            Assert.That(repaired, Is.EqualTo(Ints(c.Get("repaired_seed"))));
            Assert.That(repaired.Except(seed).Any(p => pins.Blocked[p]), Is.False, "no probe added within the keep distance");
            var unblocked = LeakRepair.Repaired(Room.Evaluator.Reference, Room.Evaluator.Tetrahedralizer, seed, Room.Wall);
            Assert.That(unblocked.Except(seed).Any(p => pins.Blocked[p]), Is.True, "without the pins the repair would add one there");
        }

        [Test]
        public void WithPinsABudgetAndAToleranceKeepThePythonReferencesProbes()
        {
            var c = Room.Golden.Get("pinned_case");
            var pins = PinnedCase(c, out var order);
            Func<SelectionSettings, LeakWeighting, SelectionResult> Place = (settings, leaks) =>
                ApplySteps.SelectByInsertion(Room.Grid, null, null, order, settings, settings.Policy == SelectionPolicy.Tolerance ? Room.Evaluator : null,
                    true, Room.Evaluator, null, CancellationToken.None, pins, leaks);
            int count = (int)Room.Golden.Get("budget").Get("count").AsNumber;
            var budget = Place(SelectionSettings.Budget(count), new LeakWeighting(Room.Wall));
            Assert.That(budget.Indices, Is.EqualTo(Ints(c.Get("budget_indices"))));
            Assert.That(budget.Indices.Length, Is.EqualTo(count), "the pins count in the budget");
            double budgetError = c.Get("budget_mean_error").AsNumber;
            Assert.That(Room.Evaluator.MeanError(budget.Indices), Is.EqualTo(budgetError).Within(1e-9 * budgetError));
            double tau = Room.Golden.Get("tolerance_case").Get("tolerance").AsNumber;
            var aware = Place(SelectionSettings.Tolerance(tau), new LeakWeighting(Room.Wall));
            Assert.That(aware.Indices, Is.EqualTo(Ints(c.Get("tolerance_indices"))));
            double error = c.Get("tolerance_mean_error").AsNumber;
            Assert.That(Room.Evaluator.MeanError(aware.Indices), Is.EqualTo(error).Within(1e-9 * error));
            var plain = Place(SelectionSettings.Tolerance(tau), null);
            Assert.That(plain.Indices, Is.EqualTo(Ints(c.Get("without_leaks"))), "the same pins, the option off");
            foreach (var placed in new[] { budget, aware, plain })
            {
                Assert.That(pins.Indices.All(p => placed.Indices.Contains(p)), Is.True, "every pin kept");
                Assert.That(placed.Indices.Except(pins.Indices).Any(p => pins.Blocked[p]), Is.False, "no new probe near a pin");
            }
            Assert.That(Room.Leaking(aware.Indices), Is.LessThan(Room.Leaking(plain.Indices)));
            Assert.Throws<PinException>(() => Place(SelectionSettings.Budget(pins.Count - 1), new LeakWeighting(Room.Wall)), "a budget below the pins");
        }

        // ---- behaviour ------------------------------------------------------------------------------------------------

        [Test]
        public void OnTheWalledRoomItLeaksLessThanTodayWithinTheTolerance()
        {
            double tau = Room.Golden.Get("tolerance_case").Get("tolerance").AsNumber;
            var plain = Room.Place(SelectionSettings.Tolerance(tau), null);
            var aware = Room.Place(SelectionSettings.Tolerance(tau), new LeakWeighting(Room.Wall));
            int plainLeaks = Room.Leaking(plain.Indices), awareLeaks = Room.Leaking(aware.Indices);
            Assert.That(plainLeaks, Is.GreaterThan(0), "today's answer must leak for the comparison to mean anything");
            Assert.That(awareLeaks, Is.LessThan(plainLeaks));
            Assert.That(Room.Evaluator.MeanError(aware.Indices), Is.LessThanOrEqualTo(tau));
            var weighted = BatchedRefinement.ToCount(Room.Evaluator.Reference, Room.Evaluator.Tetrahedralizer, aware.Indices, aware.Indices.Length,
                new LeakWeighting(Room.Wall));
            Assert.That(weighted.MeanError, Is.LessThanOrEqualTo(tau + 1e-12), "the weighted error is within tau too");
        }

        [Test]
        public void OffChangesNothingAndOnWithoutWallsChangesNothingInTheRefinement()
        {
            var reference = Room.Evaluator.Reference;
            var tet = Room.Evaluator.Tetrahedralizer;
            int[] seed = Room.Order.Prefix(64).Take(64).ToArray();
            var plain = BatchedRefinement.ToCount(reference, tet, seed, 20);
            var off = BatchedRefinement.ToCount(reference, tet, seed, 20, (LeakWeighting)null);
            var open = BatchedRefinement.ToCount(reference, tet, seed, 20, new LeakWeighting(new AnalyticBoxRaycaster()));
            var walled = BatchedRefinement.ToCount(reference, tet, seed, 20, new LeakWeighting(Room.Wall));
            Assert.That(off.Indices, Is.EqualTo(plain.Indices));
            Assert.That(off.MeanError, Is.EqualTo(plain.MeanError));
            Assert.That(open.Indices, Is.EqualTo(plain.Indices), "nothing leaks without a wall: no error is weighted");
            Assert.That(open.MeanError, Is.EqualTo(plain.MeanError));
            Assert.That(walled.Indices, Is.Not.EqualTo(plain.Indices), "the wall must change which probes go");
            var settings = SelectionSettings.Budget(20);
            var selection = ProbeSelector.SelectFromPrefixes(Room.Grid, Room.Order.Count, k => Room.Order.Prefix(k), settings, Room.Evaluator);
            Assert.That(RefinedSelection.Refine(Room.Grid, selection, k => Room.Order.Prefix(k), Room.Order.Count, settings, Room.Evaluator, null).Indices,
                Is.EqualTo(RefinedSelection.Refine(Room.Grid, selection, k => Room.Order.Prefix(k), Room.Order.Count, settings, Room.Evaluator).Indices));
        }

        [Test]
        public void TheWeightingMultipliesOnlyTheErrorsOfLeakingPoints()
        {
            var reference = Room.Evaluator.Reference;
            int[] probes = Room.Order.Prefix(16).Take(16).OrderBy(p => p).ToArray();
            var positions = probes.Select(p => reference.GetPosition(p)).ToArray();
            int[] tetrahedra = Room.Evaluator.Tetrahedralizer.Tetrahedralize(positions);
            bool[] leaking = LeakCheck.Find(reference, probes, tetrahedra, Room.Wall);
            double[] plain = PlacementError.Evaluate(reference, probes, tetrahedra).PointIrradiance;
            var state = BatchedRefinementState.Evaluate(reference, Room.Evaluator.Tetrahedralizer, probes, new LeakWeighting(Room.Wall, 3.0));
            Assert.That(leaking.Any(x => x), Is.True);
            for (int p = 0; p < reference.Count; p++)
                Assert.That(state.Errors[p], Is.EqualTo(leaking[p] ? 3.0 * plain[p] : plain[p]).Within(1e-12 * Math.Max(1, plain[p])), "point " + p);
            Assert.That(state.ErrorSum, Is.EqualTo(state.Errors.Sum()).Within(1e-9));
        }

        [TestCase(0.5, "leak weight 0.5")]
        [TestCase(double.NaN, "leak weight NaN")]
        [TestCase(double.PositiveInfinity, "leak weight ")]
        public void AWeightBelowOneOrNotFiniteIsRefusedByName(double weight, string message)
        {
            var error = Assert.Throws<PlacementErrorException>(() => new LeakWeighting(new AnalyticBoxRaycaster(), weight));
            StringAssert.Contains(message, error.Message);
            StringAssert.Contains(">= 1", error.Message);
        }

        [Test]
        public void RepairAddsOnlyLeakingPointsAndNothingWithoutWalls()
        {
            var reference = Room.Evaluator.Reference;
            var tet = Room.Evaluator.Tetrahedralizer;
            int[] probes = Room.Order.Prefix(16).Take(16).OrderBy(p => p).ToArray();
            var positions = probes.Select(p => reference.GetPosition(p)).ToArray();
            bool[] leaking = LeakCheck.Find(reference, probes, tet.Tetrahedralize(positions), Room.Wall);
            int[] once = LeakRepair.Repaired(reference, tet, probes, Room.Wall, 1);
            int[] added = once.Except(probes).ToArray();
            Assert.That(added, Is.Not.Empty);
            Assert.That(added.All(p => leaking[p]), Is.True, "only leaking points are added");
            Assert.That(LeakRepair.Repaired(reference, tet, probes, Room.Wall, 0), Is.EqualTo(probes));
            Assert.That(LeakRepair.Repaired(reference, tet, probes, new AnalyticBoxRaycaster(), 3), Is.EqualTo(probes));
            StringAssert.Contains("rounds -1", Assert.Throws<PlacementErrorException>(() => LeakRepair.Repaired(reference, tet, probes, Room.Wall, -1)).Message);
        }

        /// <summary>Counts the casts it forwards: whether a step cast any rays at all.</summary>
        private sealed class CountingRaycaster : IRaycaster
        {
            private readonly IRaycaster inner;
            public int Casts;
            public long Rays;

            public CountingRaycaster(IRaycaster inner) => this.inner = inner;

            public void Cast(Vector3[] origins, Vector3[] directions, float maxDistance, RayHit[] results)
            {
                Casts++;
                Rays += origins.Length;
                inner.Cast(origins, directions, maxDistance, results);
            }
        }

        private sealed class RecordingGroup : IProbeGroupWriter
        {
            public Vector3[] Written;
            public void Write(Vector3[] positions) => Written = positions;
        }

        /// <summary>The volume's "Avoid light leaks" as Apply passes it on (LpnnPipeline.SelectByInsertion: the physics rays;
        /// here the golden's wall): on, the Placement step's refinement casts through the volume's rays and leaks less within τ;
        /// off, or without refinement, it casts none and places what the leak-blind selection places.</summary>
        [Test]
        public void ApplyRefinesLeakAwareThroughTheVolumesRaysOnlyWhenItAvoidsLeaks()
        {
            Assert.That(ApplySteps.LeakWeightingOf(false, Room.Wall), Is.Null, "the opt-out: leak-blind");
            var weighting = ApplySteps.LeakWeightingOf(true, Room.Wall);
            Assert.That(weighting.Raycaster, Is.SameAs(Room.Wall));
            Assert.That(weighting.Weight, Is.EqualTo(LeakWeighting.DefaultWeight));
            var sh = Room.Golden.Get("sh").Items.SelectMany(JsonArrays.Floats).ToArray();
            double tau = Room.Golden.Get("tolerance_case").Get("tolerance").AsNumber;
            Func<bool, IRaycaster, SelectionResult> apply = (refine, rays) =>
            {
                var state = new ApplyState();
                state.PublishLighting(Room.Grid, sh);
                var group = new RecordingGroup();
                var placed = ApplySteps.Place(state, Room.Evaluator.Tetrahedralizer, SelectionSettings.Tolerance(tau), refine, group, null,
                    CancellationToken.None, rays);
                Assert.That(group.Written.Length, Is.EqualTo(placed.Indices.Length), "the selection is what Apply writes");
                return placed;
            };
            var aware = new CountingRaycaster(Room.Wall);
            var leakAware = apply(true, aware);
            var blind = apply(true, null);
            Assert.That(aware.Casts, Is.GreaterThan(0), "the refinement tested segments through the volume's rays");
            Assert.That(Room.Leaking(blind.Indices), Is.GreaterThan(0), "the leak-blind answer must leak for the comparison to mean anything");
            Assert.That(Room.Leaking(leakAware.Indices), Is.LessThan(Room.Leaking(blind.Indices)));
            var state0 = new ApplyState();
            state0.PublishLighting(Room.Grid, sh);
            Assert.That(new PlacementEvaluator(state0.Reference, Room.Evaluator.Tetrahedralizer).MeanError(leakAware.Indices), Is.LessThanOrEqualTo(tau));
            var unrefined = new CountingRaycaster(Room.Wall);
            Assert.That(apply(false, unrefined).Indices, Is.EqualTo(apply(false, null).Indices), "without refinement the option has nothing to act on");
            Assert.That(unrefined.Casts, Is.EqualTo(0));
        }

        // ---- remembered segments (SegmentMemo) --------------------------------------------------------------------------

        /// <summary>The memo answers as a fresh cast over the stencils of successive probe sets of the golden room (they
        /// share most segments, as a refinement's rounds do), with few slots (4: partners evicted) and the default.</summary>
        [TestCase(4)]
        [TestCase(SegmentMemo.DefaultSlots)]
        public void RememberedSegmentsAnswerAsAFreshCast(int slots)
        {
            var reference = Room.Evaluator.Reference;
            var memo = new SegmentMemo(reference.Count, slots);
            var counting = new CountingRaycaster(Room.Wall);
            long pairs = 0;
            int leaks = 0;
            foreach (int count in new[] { 8, 12, 16, 12, 24, 20, 32 })
            {
                int[] probes = Room.Order.Prefix(count).Take(count).OrderBy(p => p).ToArray();
                var positions = probes.Select(p => reference.GetPosition(p)).ToArray();
                var points = new System.Collections.Generic.List<int>();
                var stencils = new System.Collections.Generic.List<Stencil>();
                PlacementError.InterpolateOthers(reference, probes, Room.Evaluator.Tetrahedralizer.Tetrahedralize(positions), null,
                    (int n, ref Stencil stencil) =>
                    {
                        points.Add(n);
                        stencils.Add(stencil);
                    });
                bool[] fresh = LeakCheck.Leaking(reference, probes, points, stencils, Room.Wall);
                Assert.That(LeakCheck.Leaking(reference, probes, points, stencils, counting, memo), Is.EqualTo(fresh), "probes " + count);
                pairs += stencils.Sum(s => new[] { s.Weight0, s.Weight1, s.Weight2, s.Weight3 }.Count(w => w > LeakCheck.MinimumWeight));
                leaks += fresh.Count(x => x);
            }
            Assert.That(leaks, Is.GreaterThan(0), "some stencils must leak for the answers to mean anything");
            Assert.That(memo.Asked, Is.EqualTo(pairs));
            Assert.That(counting.Rays, Is.EqualTo(memo.Asked - memo.Known), "every segment not remembered is cast, once");
            Assert.That(memo.Known, Is.GreaterThan(0));
        }

        [Test]
        public void TheLeakAwareToleranceCastsMostSegmentsOnce()
        {
            var c = Room.Golden.Get("tolerance_case");
            var counting = new CountingRaycaster(Room.Wall);
            var weighting = new LeakWeighting(counting);
            var placed = Room.Place(SelectionSettings.Tolerance(c.Get("tolerance").AsNumber), weighting);
            Assert.That(placed.Indices, Is.EqualTo(Ints(c.Get("indices"))), "the same answer as the Python reference");
            var memo = weighting.MemoFor(Room.Evaluator.Reference);
            Assert.That(counting.Rays, Is.EqualTo(memo.Asked - memo.Known), "the repair and the refinement share the memo");
            Assert.That(counting.Rays, Is.LessThan(memo.Asked / 2), "most segments asked again were remembered");
        }

        [Test]
        public void AMemoOfAnotherReferenceIsRefused()
        {
            var reference = Room.Evaluator.Reference;
            Assert.Throws<ArgumentException>(() => LeakCheck.Leaking(reference, new[] { 0, 1, 2, 3 }, new int[0], new Stencil[0], Room.Wall,
                new SegmentMemo(reference.Count + 1)));
            Assert.Throws<ArgumentOutOfRangeException>(() => new SegmentMemo(10, 3));
        }

        /// <summary>Cancels its source on the first cast, so a repair is cancelled during its first round.</summary>
        private sealed class CancellingRaycaster : IRaycaster
        {
            private readonly IRaycaster inner;
            private readonly CancellationTokenSource source;
            public int Casts;

            public CancellingRaycaster(IRaycaster inner, CancellationTokenSource source)
            {
                this.inner = inner;
                this.source = source;
            }

            public void Cast(Vector3[] origins, Vector3[] directions, float maxDistance, RayHit[] results)
            {
                Casts++;
                source.Cancel();
                inner.Cast(origins, directions, maxDistance, results);
            }
        }

        [Test]
        public void ACancelIsHonouredBetweenRepairRounds()
        {
            var reference = Room.Evaluator.Reference;
            int[] probes = Room.Order.Prefix(16).Take(16).ToArray();
            using (var source = new CancellationTokenSource())
            {
                var rays = new CancellingRaycaster(Room.Wall, source);
                Assert.Throws<OperationCanceledException>(() => LeakRepair.Repaired(reference, Room.Evaluator.Tetrahedralizer, probes, rays, 2, source.Token));
                int castsInOneRound = rays.Casts;
                Assert.That(castsInOneRound, Is.GreaterThan(0), "the first round ran");
                Assert.That(LeakRepair.Repaired(reference, Room.Evaluator.Tetrahedralizer, probes, Room.Wall, 1).Length, Is.GreaterThan(probes.Length),
                    "the first round added probes, so a second round would have cast again");
            }
        }
    }
}
