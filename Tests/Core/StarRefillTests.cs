using System;
using System.Collections.Generic;
using System.Linq;
using System.Numerics;
using Lpnn.Probes.Core.Quality;
using Lpnn.Probes.Core.Tests.Support;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    /// <summary>The batched refinement's star refills (StarRefills, HoleWrap, TetrahedraAfterRemoval; Documentation~/quality.md
    /// §5.3): a trial's and a commit's tetrahedra derived from the candidates' refilled stars must be exactly those a
    /// tetrahedralisation of the remaining probes gives — checked against Bowyer–Watson (Tests/Core/Support), an
    /// independent tetrahedraliser, tie-broken with the same heights on lattices — and a refinement must keep the same
    /// probes with them as when it tetrahedralises every set. Port of Training~/tests/quality/test_quality_trial_fills.py.</summary>
    [TestFixture]
    public class StarRefillTests
    {
        /// <summary>The greedy independent set of the state's Delaunay graph in the given order of probes.</summary>
        private static int[] Independent(BatchedRefinementState state, IEnumerable<int> order)
        {
            var blocked = new HashSet<int>();
            var chosen = new List<int>();
            foreach (int p in order)
            {
                if (blocked.Contains(p)) continue;
                chosen.Add(p);
                int k = Array.BinarySearch(state.Probes, p);
                for (int e = state.EdgeStart[k]; e < state.EdgeStart[k + 1]; e++) blocked.Add(state.EdgeTarget[e]);
            }
            return chosen.ToArray();
        }

        /// <summary>The probes with those on the box's corners (hull vertices) first, or in a random order.</summary>
        private static IEnumerable<int> Order(ReferenceLighting reference, int[] probes, bool cornersFirst, int seed)
        {
            if (!cornersFirst) return probes.OrderBy(p => new Random(seed * 7919 + p).Next()).ToArray();
            double[] local = reference.Local;
            Func<int, bool> corner = p => Enumerable.Range(0, 3).All(axis =>
                local[3 * p + axis] == probes.Min(q => local[3 * q + axis]) || local[3 * p + axis] == probes.Max(q => local[3 * q + axis]));
            return probes.Where(corner).Concat(probes.Where(p => !corner(p))).ToArray();
        }

        /// <summary>Each tetrahedron (global ids) as its sorted vertices, all of them sorted.</summary>
        private static List<string> Sets(int[] tetrahedra, int[] probes, int corners = 4)
        {
            var sets = new List<string>();
            for (int t = 0; t < tetrahedra.Length; t += corners)
                sets.Add(string.Join(",", Enumerable.Range(0, corners).Select(j => probes[tetrahedra[t + j]]).OrderBy(v => v)));
            sets.Sort(StringComparer.Ordinal);
            return sets;
        }

        private static TetrahedralMesh Fresh(ReferenceLighting reference, ITetrahedralizer tetrahedralizer, int[] probes) =>
            TetrahedralMesh.Build(PlacementError.ProbePoints(reference, probes), tetrahedralizer.Tetrahedralize(probes.Select(reference.GetPosition).ToArray()));

        /// <summary>The refills of the candidates' stars and the tetrahedra derived from them, or nulls.</summary>
        private static int[] Derived(ReferenceLighting reference, ITetrahedralizer tetrahedralizer, BatchedRefinementState state, int[] candidates,
            out int[] remaining, out StarRefills refills, out int linkCalls)
        {
            refills = StarRefills.Of(reference, tetrahedralizer, state.Probes, state.Mesh, state.EdgeStart, state.EdgeTarget, candidates, out linkCalls);
            remaining = BatchedRefinementState.ProbesWithout(state.Probes, candidates, reference.Count);
            if (refills == null) return null;
            var removed = new bool[reference.Count];
            foreach (int c in candidates) removed[c] = true;
            return TetrahedraAfterRemoval.Derive(reference.Local, state.Probes, state.Mesh, removed, remaining, refills.Tetrahedra, refills.Owners);
        }

        private static void AssertRefillsAreTheTetrahedralisation(ReferenceLighting reference, ITetrahedralizer tetrahedralizer, int[] probes,
            bool cornersFirst, int seed, out int linkCalls)
        {
            Array.Sort(probes);
            var state = BatchedRefinementState.Evaluate(reference, tetrahedralizer, probes);
            int[] candidates = Independent(state, Order(reference, state.Probes, cornersFirst, seed));
            int[] derived = Derived(reference, tetrahedralizer, state, candidates, out int[] remaining, out var refills, out linkCalls);
            Assert.That(refills, Is.Not.Null, "the stars were refilled");
            Assert.That(derived, Is.Not.Null, "the derived tetrahedra were accepted");
            Assert.That(refills.Tetrahedra.Length, Is.GreaterThan(0));
            var fresh = Fresh(reference, tetrahedralizer, remaining);
            Assert.That(Sets(derived, remaining), Is.EqualTo(Sets(fresh.Tetrahedra, remaining)),
                candidates.Length + " candidates removed from " + probes.Length + " probes");
        }

        [TestCase(false, 1)]
        [TestCase(false, 2)]
        [TestCase(true, 3)]
        public void OnALatticeWithTiesTheRefillsAreTheTieBrokenTetrahedralisation(bool cornersFirst, int seed)
        {
            var reference = RefinementFixtures.Lattice(6, 5, 4);
            AssertRefillsAreTheTetrahedralisation(reference, BowyerWatsonDelaunay.TieBroken(reference), Enumerable.Range(0, reference.Count).ToArray(),
                cornersFirst, seed, out int linkCalls);
            // The box's corners are hull vertices, refilled from their links (a corner whose star is one tetrahedron, with
            // no call: the hull loses it whole).
            if (cornersFirst) Assert.That(linkCalls, Is.GreaterThan(0));
        }

        [Test]
        public void OnALatticeSubsetWithTiesTheRefillsAreTheTieBrokenTetrahedralisation()
        {
            var reference = RefinementFixtures.Lattice(7, 6, 5);
            int[] probes = Enumerable.Range(0, reference.Count).Where(p => new Random(p * 31 + 5).NextDouble() < 0.5).ToArray();
            AssertRefillsAreTheTetrahedralisation(reference, BowyerWatsonDelaunay.TieBroken(reference), probes, false, 4, out _);
        }

        [TestCase(120, 11)]
        [TestCase(200, 12)]
        [TestCase(200, 13)]
        public void InARandomCloudTheRefillsAreTheDelaunayTetrahedralisation(int count, int seed)
        {
            var reference = RefinementFixtures.Cloud(count, seed);
            AssertRefillsAreTheTetrahedralisation(reference, new BowyerWatsonDelaunay(), Enumerable.Range(0, count).ToArray(), false, seed, out _);
        }

        [Test]
        public void AHullVertexIsRefilledFromItsLinkAndTheHullShrinks()
        {
            var reference = RefinementFixtures.Cloud(150, 21);
            var tetrahedralizer = new CountingTetrahedralizer(new BowyerWatsonDelaunay());
            int[] probes = Enumerable.Range(0, reference.Count).ToArray();
            var state = BatchedRefinementState.Evaluate(reference, tetrahedralizer, probes);
            // The points extreme along an axis are hull vertices; first in the order, each is a candidate.
            double[] local = reference.Local;
            var extreme = Enumerable.Range(0, 3).SelectMany(axis => new[]
            {
                probes.OrderBy(p => local[3 * p + axis]).First(), probes.OrderBy(p => -local[3 * p + axis]).First()
            }).Distinct().ToArray();
            int[] candidates = Independent(state, extreme.Concat(probes.Where(p => !extreme.Contains(p))));
            int[] derived = Derived(reference, tetrahedralizer, state, candidates, out int[] remaining, out _, out int linkCalls);
            Assert.That(candidates.Intersect(extreme).Count(), Is.GreaterThanOrEqualTo(2));
            Assert.That(linkCalls, Is.GreaterThanOrEqualTo(candidates.Intersect(extreme).Count()));
            Assert.That(tetrahedralizer.Links, Is.EqualTo(linkCalls));
            var fresh = Fresh(reference, new BowyerWatsonDelaunay(), remaining);
            Assert.That(Sets(derived, remaining), Is.EqualTo(Sets(fresh.Tetrahedra, remaining)));
            Assert.That(Sets(TetrahedralMesh.Build(PlacementError.ProbePoints(reference, remaining), derived).HullFaces, remaining, 3),
                Is.EqualTo(Sets(fresh.HullFaces, remaining, 3)), "the hull lost the removed hull vertices");
        }

        [Test]
        public void TheDerivedMeshIsTheMeshAssembledFromScratch()
        {
            var reference = RefinementFixtures.Lattice(6, 5, 4);
            var tetrahedralizer = BowyerWatsonDelaunay.TieBroken(reference);
            var state = BatchedRefinementState.Evaluate(reference, tetrahedralizer, Enumerable.Range(0, reference.Count).ToArray());
            int[] candidates = Independent(state, Order(reference, state.Probes, true, 5));
            int[] derived = Derived(reference, tetrahedralizer, state, candidates, out int[] remaining, out _, out _);
            var mesh = TetrahedralMesh.Build(PlacementError.ProbePoints(reference, remaining), derived);
            var fresh = Fresh(reference, tetrahedralizer, remaining);
            Assert.That(mesh.HasTheTetrahedraOf(fresh), Is.True);
            Assert.That(Sets(mesh.HullFaces, remaining, 3), Is.EqualTo(Sets(fresh.HullFaces, remaining, 3)));
            // Every tetrahedron positively oriented, with the transform a fresh build gives it (the same vertex order kept).
            var rebuilt = TetrahedralMesh.Build(PlacementError.ProbePoints(reference, remaining), mesh.Tetrahedra);
            Assert.That(rebuilt.Tetrahedra, Is.EqualTo(mesh.Tetrahedra));
            Assert.That(rebuilt.Inverse, Is.EqualTo(mesh.Inverse));
        }

        [Test]
        public void DerivedTetrahedraThatAreNotATetrahedralisationAreRefused()
        {
            var reference = RefinementFixtures.Cloud(150, 31);
            var tetrahedralizer = new BowyerWatsonDelaunay();
            var state = BatchedRefinementState.Evaluate(reference, tetrahedralizer, Enumerable.Range(0, reference.Count).ToArray());
            int[] candidates = Independent(state, Order(reference, state.Probes, false, 6));
            Assert.That(Derived(reference, tetrahedralizer, state, candidates, out int[] remaining, out var refills, out _), Is.Not.Null);
            var removed = new bool[reference.Count];
            foreach (int c in candidates) removed[c] = true;
            Func<int[], int[], int[]> derive = (added, owners) =>
                TetrahedraAfterRemoval.Derive(reference.Local, state.Probes, state.Mesh, removed, remaining, added, owners);
            // A refill tetrahedron missing: a hole (a new crack, or a probe in no tetrahedron).
            for (int drop = 0; drop < refills.Owners.Length; drop += 7)
            {
                var added = refills.Tetrahedra.Where((v, i) => i / 4 != drop).ToArray();
                var owners = refills.Owners.Where((v, i) => i != drop).ToArray();
                Assert.That(derive(added, owners), Is.Null, "refill tetrahedron " + drop + " dropped");
            }
            // A refill tetrahedron twice: its faces in three tetrahedra.
            Assert.That(derive(refills.Tetrahedra.Concat(refills.Tetrahedra.Take(4)).ToArray(), refills.Owners.Concat(refills.Owners.Take(1)).ToArray()),
                Is.Null, "a refill tetrahedron repeated");
            Assert.That(derive(refills.Tetrahedra, refills.Owners), Is.Not.Null);
        }

        [Test]
        public void ARefusedStarFallsBackToTheTetrahedralisation()
        {
            var reference = RefinementFixtures.Cloud(150, 41);
            int[] probes = Enumerable.Range(0, reference.Count).ToArray();
            double[] local = reference.Local;
            int lowest = probes.OrderBy(p => local[3 * p]).First();  // a hull vertex: refilled from its link
            var honest = new CountingTetrahedralizer(new BowyerWatsonDelaunay());
            var expected = new double[reference.Count];
            var fresh = BatchedRefinementState.Evaluate(reference, honest, probes);
            int[] candidates = Independent(fresh, new[] { lowest }.Concat(probes.Where(p => p != lowest)));
            int[] remaining = BatchedRefinementState.ProbesWithout(fresh.Probes, candidates, reference.Count);
            BatchedRefinementState.ForceTetrahedralisation = true;
            try
            {
                fresh.RemovalCosts(reference, honest, remaining, candidates, expected);
            }
            finally
            {
                BatchedRefinementState.ForceTetrahedralisation = false;
            }
            // The link's answer empty (refused by StarRefills), or missing its last tetrahedron (a hole the volume or the
            // derived mesh's checks refuse): either way the trial tetrahedralises the remaining probes, with the same costs.
            var answers = new Func<Vector3[], int[], int[]>[] { (positions, tets) => new int[0], (positions, tets) => tets.Take(tets.Length - 4).ToArray() };
            foreach (var answer in answers)
            {
                var broken = new CountingTetrahedralizer(new BowyerWatsonDelaunay(), answer);
                var state = BatchedRefinementState.Evaluate(reference, broken, probes);
                if (answer == answers[0])
                    Assert.That(StarRefills.Of(reference, broken, state.Probes, state.Mesh, state.EdgeStart, state.EdgeTarget, candidates, out _), Is.Null);
                var costs = new double[reference.Count];
                int before = broken.Whole;
                state.RemovalCosts(reference, broken, remaining, candidates, costs);
                Assert.That(broken.Links, Is.GreaterThanOrEqualTo(2), "each call made twice: once above, once by the trial");
                Assert.That(broken.Whole, Is.EqualTo(before + 1), "the trial was tetrahedralised");
                Assert.That(state.Counts.Derived, Is.EqualTo(0));
                Assert.That(costs, Is.EqualTo(expected));
            }
        }

        /// <summary>A refinement with refills against the same one tetrahedralising every trial and commit.</summary>
        private static void AssertTheSameProbes(ReferenceLighting reference, Func<ITetrahedralizer> tetrahedralizer, Func<ITetrahedralizer, BatchedRefinementResult> refine,
            bool refillsExpected)
        {
            var withRefills = new CountingTetrahedralizer(tetrahedralizer());
            var refilled = refine(withRefills);
            var forced = new CountingTetrahedralizer(tetrahedralizer());
            BatchedRefinementResult tetrahedralised;
            BatchedRefinementState.ForceTetrahedralisation = true;
            try
            {
                tetrahedralised = refine(forced);
            }
            finally
            {
                BatchedRefinementState.ForceTetrahedralisation = false;
            }
            Assert.That(refilled.Indices, Is.EqualTo(tetrahedralised.Indices));
            Assert.That(refilled.Rounds, Is.EqualTo(tetrahedralised.Rounds));
            Assert.That(refilled.MeanError, Is.EqualTo(tetrahedralised.MeanError).Within(1e-12));
            Assert.That(forced.Links, Is.EqualTo(0));
            Assert.That(tetrahedralised.Rounds, Is.GreaterThan(3));
            if (refillsExpected)
                Assert.That(withRefills.Whole, Is.LessThan(forced.Whole / 3), "whole tetrahedralisations with refills (" + withRefills.Links + " links) against without");
            else  // every trial's check disagrees and answers it, and every commit is tetrahedralised: as many calls as without
                Assert.That(withRefills.Whole, Is.EqualTo(forced.Whole), "one check per trial in place of its tetrahedralisation");
        }

        [Test]
        public void ARefinementOnALatticeKeepsTheSameProbesWithRefillsAsWithTetrahedralisations()
        {
            var reference = RefinementFixtures.Lattice(7, 6, 5);
            int[] seed = Enumerable.Range(0, reference.Count).Where(p => p % 3 != 1).ToArray();
            AssertTheSameProbes(reference, () => BowyerWatsonDelaunay.TieBroken(reference),
                t => BatchedRefinement.WithinTolerance(reference, t, seed, 0.02), true);
            AssertTheSameProbes(reference, () => BowyerWatsonDelaunay.TieBroken(reference), t => BatchedRefinement.ToCount(reference, t, seed, 12), true);
        }

        [Test]
        public void ARefinementOfARandomCloudKeepsTheSameProbesWithRefillsAsWithTetrahedralisations()
        {
            var reference = RefinementFixtures.Cloud(200, 51);
            AssertTheSameProbes(reference, () => new BowyerWatsonDelaunay(), t => BatchedRefinement.ToCount(reference, t, Enumerable.Range(0, 200).ToArray(), 15), true);
        }

        [Test]
        public void ATetrahedraliserThatBreaksTiesOtherwiseIsFollowedAtEveryTrial()
        {
            var reference = RefinementFixtures.Lattice(6, 5, 4);
            int[] probes = Enumerable.Range(0, reference.Count).ToArray();
            var otherwise = new CountingTetrahedralizer(BowyerWatsonDelaunay.TieBroken(reference, otherwise: true));
            var state = BatchedRefinementState.Evaluate(reference, otherwise, probes);
            int[] candidates = Independent(state, Order(reference, state.Probes, false, 8));
            int[] remaining = BatchedRefinementState.ProbesWithout(state.Probes, candidates, reference.Count);
            var costs = new double[reference.Count];
            state.RemovalCosts(reference, otherwise, remaining, candidates, costs);
            Assert.That(state.Counts.Derived, Is.EqualTo(1), "the refills gave a tetrahedralisation");
            Assert.That(state.Counts.Check.Agrees, Is.False, "but not this tetrahedraliser's");
            Assert.That(state.Counts.Check.Resyncs, Is.EqualTo(1));
            Assert.That(otherwise.Whole, Is.EqualTo(2), "the seed, then the trial's check");
            for (int again = 2; again <= DerivationCheck.MaxResyncs; again++)
            {
                state.RemovalCosts(reference, otherwise, remaining, candidates, costs);
                Assert.That(state.Counts.Derived, Is.EqualTo(again), "the refills are still tried");
                Assert.That(state.Counts.Check.Resyncs, Is.EqualTo(again), "and checked again, since none has agreed");
                Assert.That(otherwise.Whole, Is.EqualTo(1 + again));
            }
            int links = otherwise.Links;
            state.RemovalCosts(reference, otherwise, remaining, candidates, costs);
            Assert.That(otherwise.Links, Is.EqualTo(links), "no refills after MaxResyncs disagreements");
            Assert.That(otherwise.Whole, Is.EqualTo(2 + DerivationCheck.MaxResyncs));
            AssertTheSameProbes(reference, () => BowyerWatsonDelaunay.TieBroken(reference, otherwise: true), t => BatchedRefinement.ToCount(reference, t, probes, 12), false);
        }

        [Test]
        public void ADisagreeingTrialReSynchronisesAndTheNextDerivesAgain()
        {
            // The first trial is checked against a tetrahedraliser that breaks the lattice's ties otherwise (as a degenerate
            // star's refill may differ from the tetrahedraliser's): its answer replaces the trial, the commit is
            // tetrahedralised, and the next trial derives from that again and, checked against the same tie rule, agrees.
            var reference = RefinementFixtures.Lattice(6, 5, 4);
            int[] probes = Enumerable.Range(0, reference.Count).ToArray();
            var same = new CountingTetrahedralizer(BowyerWatsonDelaunay.TieBroken(reference));
            var links = BowyerWatsonDelaunay.TieBroken(reference);  // a star's link as the refills expect it
            var otherwise = new CountingTetrahedralizer(BowyerWatsonDelaunay.TieBroken(reference, otherwise: true), (positions, _) => links.Tetrahedralize(positions));
            var state = BatchedRefinementState.Evaluate(reference, same, probes);
            int[] candidates = Independent(state, Order(reference, state.Probes, false, 8));
            var costs = new double[reference.Count];
            state.RemovalCosts(reference, otherwise, BatchedRefinementState.ProbesWithout(state.Probes, candidates, reference.Count), candidates, costs);
            Assert.That(state.Counts.Check.Resyncs, Is.EqualTo(1));
            Assert.That(state.Counts.Check.Agrees, Is.False);
            var next = state.Without(reference, same, candidates.Take(3).ToArray());
            Assert.That(same.Whole, Is.EqualTo(2), "the seed, then the commit after the disagreement");
            int tetrahedralised = state.Counts.Tetrahedralised;
            int[] again = Independent(next, Order(reference, next.Probes, false, 8));
            next.RemovalCosts(reference, same, BatchedRefinementState.ProbesWithout(next.Probes, again, reference.Count), again, costs);
            Assert.That(next.Counts.Check.Agrees, Is.True, "the re-synchronised set derives the tetrahedraliser's tetrahedra");
            Assert.That(next.Counts.Check.Resyncs, Is.EqualTo(1));
            Assert.That(same.Whole, Is.EqualTo(3), "one check");
            var third = next.Without(reference, same, again.Take(3).ToArray());
            int[] later = Independent(third, Order(reference, third.Probes, false, 8));
            third.RemovalCosts(reference, same, BatchedRefinementState.ProbesWithout(third.Probes, later, reference.Count), later, costs);
            Assert.That(same.Whole, Is.EqualTo(3), "the commit and the next trial derived, unchecked");
            Assert.That(third.Counts.Tetrahedralised, Is.EqualTo(tetrahedralised + 1), "only the one check since the re-sync");
        }

        [Test]
        public void TheTieHeightsAreThoseOfPythonsTetrahedralisation()
        {
            // lpnn.quality.metric.triangulation.position_hash of these float64 positions (computed with the Python
            // reference, 2026-11-27: position_hash(np.array([[0.0, 0.0, 0.0], [1.5, -2.25, 1e6]]))).
            Assert.That(TieBreak.PositionHash(0.0, 0.0, 0.0), Is.EqualTo(PythonHashOfOrigin));
            Assert.That(TieBreak.PositionHash(1.5, -2.25, 1e6), Is.EqualTo(PythonHashOfOther));
            // The spacing: the median nearest-neighbour distance, a duplicate's 0 left out.
            double[] local = { 0, 0, 0, 0, 0, 0, 0.1, 0, 0, 0.3, 0, 0, 0.3, 0.5, 0 };
            Assert.That(TieBreak.MedianSpacing(local), Is.EqualTo(0.2).Within(1e-15));
        }

        private const double PythonHashOfOrigin = 0.20310281705476096;
        private const double PythonHashOfOther = 0.4367823002305987;
    }
}
