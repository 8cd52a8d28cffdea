using System;
using System.Linq;
using System.Numerics;
using Lpnn.Probes.Core.Quality;
using Lpnn.Probes.Core.Tests.Support;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    /// <summary>A batched refinement keeps the fresh costs of candidates off the boundary instead of measuring them again
    /// (BatchedRefinement step 2, BatchedRefinementState.BoundaryVertices; Documentation~/quality.md §5.3): the same
    /// probes as re-measuring every cost, with fewer costs measured and no more whole tetrahedralisations (a commit of
    /// candidates the trial left out refills their stars itself). Port of Training~/tests/quality/test_quality_batched_reuse.py.</summary>
    [TestFixture]
    public class FreshCostTests
    {
        [TearDown]
        public void Restore()
        {
            BatchedRefinement.RemeasureFreshCostsForTests = false;
            BatchedRefinement.TrialListener = null;
        }

        private static BatchedRefinementResult Refine(ReferenceLighting reference, Func<ITetrahedralizer> tetrahedralizer, string goal,
            bool remeasure, out int measured, out int candidates, out int calls)
        {
            int m = 0, c = 0;
            BatchedRefinement.RemeasureFreshCostsForTests = remeasure;
            BatchedRefinement.TrialListener = (all, trial) => { c += all; m += trial; };
            var counting = new CountingTetrahedralizer(tetrahedralizer());
            int[] seed = Enumerable.Range(0, reference.Count).Where(p => p % 3 != 1).ToArray();
            var result = goal == "tolerance"
                ? BatchedRefinement.WithinTolerance(reference, counting, seed, 0.02)
                : BatchedRefinement.ToCount(reference, counting, seed, 12);
            measured = m;
            candidates = c;
            calls = counting.Whole;
            return result;
        }

        [TestCase("lattice", "tolerance")]
        [TestCase("lattice", "count")]
        [TestCase("cloud", "tolerance")]
        [TestCase("cloud", "count")]
        public void KeepingFreshCostsGivesTheProbesOfMeasuringEveryCost(string which, string goal)
        {
            var reference = which == "lattice" ? RefinementFixtures.Lattice(7, 6, 5) : RefinementFixtures.Cloud(240, 51);
            Func<ITetrahedralizer> tetrahedralizer = () => which == "lattice" ? BowyerWatsonDelaunay.TieBroken(reference) : new BowyerWatsonDelaunay();
            var kept = Refine(reference, tetrahedralizer, goal, false, out int measured, out int candidates, out int calls);
            var every = Refine(reference, tetrahedralizer, goal, true, out int measuredEvery, out int candidatesEvery, out int callsEvery);
            Assert.That(kept.Indices, Is.EqualTo(every.Indices));
            Assert.That(kept.Rounds, Is.EqualTo(every.Rounds));
            Assert.That(kept.MeanError, Is.EqualTo(every.MeanError).Within(1e-12));
            Assert.That(kept.Rounds, Is.GreaterThan(3), "too few rounds to tell");
            Assert.That(candidates, Is.EqualTo(candidatesEvery), "the same candidates each round");
            Assert.That(measuredEvery, Is.EqualTo(candidatesEvery));
            Assert.That(measured, Is.LessThan(candidates), "some fresh costs kept: else this tests nothing");
            Assert.That(calls, Is.LessThanOrEqualTo(callsEvery), "a commit of kept candidates refills their stars, not the tetrahedraliser");
        }

        [Test]
        public void TheBoundaryIsEveryProbeOnAHullFace()
        {
            var reference = RefinementFixtures.Lattice(3, 3, 3);
            int[] probes = Enumerable.Range(0, reference.Count).ToArray();
            var state = BatchedRefinementState.Evaluate(reference, BowyerWatsonDelaunay.TieBroken(reference), probes);
            bool[] boundary = state.BoundaryVertices(reference.Count);
            int centre = Array.FindIndex(QualityFixtures.Positions(QualityFixtures.Box(3, 3, 3)), v => v == new Vector3(1f, 1f, 1f));
            Assert.That(centre, Is.GreaterThanOrEqualTo(0));
            for (int p = 0; p < reference.Count; p++) Assert.That(boundary[p], Is.EqualTo(p != centre), "point " + p);
        }
    }
}
