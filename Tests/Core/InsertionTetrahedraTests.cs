using System;
using System.Linq;
using System.Numerics;
using Lpnn.Probes.Core.Quality;
using Lpnn.Probes.Core.Tests.Support;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    /// <summary>Insertion rounds derived by insertion (RegularInsertion, InsertionTetrahedra; Documentation~/quality.md §5.1
    /// step 6): a tetrahedralisation grown by inserting points must be exactly the one a fresh tetrahedralisation of all
    /// the points gives — checked against Bowyer–Watson (Tests/Core/Support), an independent tetrahedraliser, lifted by
    /// the same tie heights on lattices — and an insertion order must rank the same points with derived rounds as with
    /// every round tetrahedralised, fall back where the derivation fails, and stop deriving when the tetrahedraliser
    /// breaks ties otherwise.</summary>
    [TestFixture]
    public class InsertionTetrahedraTests
    {
        [TearDown]
        public void Restore()
        {
            InsertionTetrahedra.Setting = InsertionTetrahedra.Mode.Derived;
            InsertionTetrahedra.AlterDerivedForTests = null;
        }

        // ---- the derivation against a fresh tetrahedralisation ----------------------------------------------------------

        /// <summary>Tetrahedralises the first <paramref name="initial"/> points with Bowyer–Watson, inserts the rest one by
        /// one, and asserts the set of tetrahedra is Bowyer–Watson's of all of them.</summary>
        private static void AssertInsertionIsTheTetrahedralisation(double[] local, double[] heights, int[] order, int initial)
        {
            int[] first = order.Take(initial).ToArray();
            var mesh = RegularInsertion.Of(local, heights, first, BowyerWatson(local, heights, first), out string refused);
            Assert.That(mesh, Is.Not.Null, "the starting tetrahedralisation was refused: " + refused);
            for (int k = initial; k < order.Length; k++)
                Assert.That(mesh.TryInsert(order[k]), Is.True, "inserting point " + order[k] + " failed: " + mesh.Failure);
            int[] expected = BowyerWatson(local, heights, order);
            var points = new double[3 * order.Length];
            for (int k = 0; k < order.Length; k++) Array.Copy(local, 3 * order[k], points, 3 * k, 3);
            int[] derived = mesh.Tetrahedra();
            Assert.That(derived.Length, Is.EqualTo(expected.Length), "tetrahedron count");
            Assert.That(TetrahedralMesh.Build(points, derived).HasTheTetrahedraOf(TetrahedralMesh.Build(points, expected)), Is.True,
                "the inserted tetrahedra are not Bowyer–Watson's");
            Assert.That(TetrahedronNumbering.Numbered(derived, order), Is.EqualTo(TetrahedronNumbering.Numbered(expected, order)),
                "numbered alike, though built otherwise");
        }

        /// <summary>Bowyer–Watson's tetrahedra of the given points (indices into <paramref name="vertices"/>).</summary>
        private static int[] BowyerWatson(double[] local, double[] heights, int[] vertices)
        {
            var points = new double[vertices.Length, 3];
            var lifted = new double[vertices.Length];
            for (int k = 0; k < vertices.Length; k++)
            {
                for (int a = 0; a < 3; a++) points[k, a] = local[3 * vertices[k] + a];
                lifted[k] = heights[vertices[k]];
            }
            return BowyerWatsonDelaunay.Tetrahedralize(points, lifted);
        }

        /// <summary>An nx × ny × nz lattice of the given cell from <paramref name="offset"/>, x, y, z per point, and tie
        /// heights of 1e-5 of the squared cell from TieBreak's position hash (every cell's corners are cospherical).</summary>
        private static double[] Lattice(int nx, int ny, int nz, double cell, double offset, out double[] heights)
        {
            var local = new double[3 * nx * ny * nz];
            heights = new double[nx * ny * nz];
            int n = 0;
            for (int x = 0; x < nx; x++)
            for (int y = 0; y < ny; y++)
            for (int z = 0; z < nz; z++, n++)
            {
                local[3 * n] = offset + x * cell;
                local[3 * n + 1] = offset + y * cell;
                local[3 * n + 2] = offset + z * cell;
                heights[n] = TieBreak.Fraction * cell * cell * TieBreak.PositionHash(local[3 * n], local[3 * n + 1], local[3 * n + 2]);
            }
            return local;
        }

        private static int[] Shuffled(int count, int seed)
        {
            var random = new Random(seed);
            return Enumerable.Range(0, count).OrderBy(_ => random.Next()).ToArray();
        }

        [TestCase(1)]
        [TestCase(2)]
        [TestCase(3)]
        public void InARandomCloudInsertionGivesTheDelaunayTetrahedralisation(int seed)
        {
            var random = new Random(seed);
            var local = new double[3 * 300];
            for (int k = 0; k < local.Length; k++) local[k] = random.NextDouble() * (k % 3 + 1);
            AssertInsertionIsTheTetrahedralisation(local, new double[300], Shuffled(300, seed), 30);
        }

        [TestCase(4)]
        [TestCase(5)]
        public void OnATiedLatticeInsertionGivesTheTieBrokenTetrahedralisation(int seed)
        {
            double[] local = Lattice(6, 5, 5, 1.0, 0.0, out double[] heights);
            AssertInsertionIsTheTetrahedralisation(local, heights, Shuffled(local.Length / 3, seed), 20);
        }

        [Test]
        public void PointsOutsideTheHullGrowItOnTheLatticesPlanesToo()
        {
            // The first points are the inner 3 × 3 × 3 block of a 7 × 6 × 5 lattice: every later point is outside their hull,
            // many of them in the plane of one of its faces.
            double[] local = Lattice(7, 6, 5, 1.0, 0.0, out double[] heights);
            int count = local.Length / 3;
            Func<int, bool> inner = n => Enumerable.Range(0, 3).All(a => local[3 * n + a] >= 1 && local[3 * n + a] <= 3);
            int[] order = Enumerable.Range(0, count).Where(inner).Concat(Enumerable.Range(0, count).Where(n => !inner(n))).ToArray();
            AssertInsertionIsTheTetrahedralisation(local, heights, order, 27);
        }

        // Cells of 2^-13 (~1.2e-4) and 2^13 (~8.2e3), exact in binary so that the lattice's planes are exactly planar: with
        // a cell of 1e-4 the rounded lattice's diagonal planes bend by ~1e-20, its exact tetrahedralisation has slivers,
        // and the test's Bowyer–Watson (plain double) no longer gives a tetrahedralisation to compare with.
        [TestCase(1.0 / 8192, 0.0)]
        [TestCase(8192.0, 0.0)]
        [TestCase(1.0, 1e4)]
        [TestCase(1.0 / 8192, 1e4)]
        public void TheInsertionHoldsAtAnyCellSizeAndFarFromTheOrigin(double cell, double offset)
        {
            double[] local = Lattice(5, 5, 4, cell, offset, out double[] heights);
            AssertInsertionIsTheTetrahedralisation(local, heights, Shuffled(local.Length / 3, 7), 12);
        }

        [Test]
        public void ATetrahedralisationWithACrackIsRefused()
        {
            // A lattice's tetrahedralisation less one inner tetrahedron (a dropped flat one leaves such a hole): not convex
            // and closed, so nothing may be inserted into it.
            double[] local = Lattice(4, 4, 4, 1.0, 0.0, out double[] heights);
            int[] all = Enumerable.Range(0, local.Length / 3).ToArray();
            int[] tets = BowyerWatson(local, heights, all);
            int inner = Enumerable.Range(0, tets.Length / 4).First(t => Enumerable.Range(0, 4).All(j =>
                Enumerable.Range(0, 3).All(a => local[3 * tets[4 * t + j] + a] > 0 && local[3 * tets[4 * t + j] + a] < 3)));
            int[] cracked = tets.Where((_, k) => k / 4 != inner).ToArray();
            Assert.That(RegularInsertion.Of(local, heights, all, tets, out _), Is.Not.Null);
            Assert.That(RegularInsertion.Of(local, heights, all, cracked, out string failure), Is.Null);
            Assert.That(failure, Is.EqualTo("the hull in pieces (a crack inside)"));
        }

        // ---- an insertion order's rounds ---------------------------------------------------------------------------------

        private static ReferenceLighting LatticeLighting(Grid.EvaluationGrid grid)
        {
            var positions = QualityFixtures.Positions(grid);
            return ReferenceLighting.Create(positions, QualityFixtures.BlobField(positions, new Vector3(1.5f, 1.5f, 1f), new Vector3(4.5f, 2.5f, 2f), 0.8f));
        }

        /// <summary>The whole ranking of a lattice with the mode set, and the tetrahedraliser's calls and the order's counts.</summary>
        private static int[] Ranking(InsertionTetrahedra.Mode mode, bool otherwise, out int calls, out InsertionTetrahedra counts)
        {
            var grid = QualityFixtures.Box(7, 6, 5);
            var reference = LatticeLighting(grid);
            var tetrahedralizer = BowyerWatsonDelaunay.TieBroken(reference, otherwise);
            InsertionTetrahedra.Setting = mode;
            var order = new InsertionOrder(grid, reference, tetrahedralizer, 0.3);
            int[] ranking = order.All();
            calls = tetrahedralizer.Calls;
            counts = order.Tetrahedra;
            Assert.That(order.Rounds, Is.GreaterThan(5), "too few rounds to tell");
            return ranking;
        }

        [Test]
        public void DerivedRoundsRankAsTetrahedralisedOnesWithFarFewerCalls()
        {
            int[] everyRound = Ranking(InsertionTetrahedra.Mode.Tetrahedralised, false, out int tetrahedralised, out _);
            int[] derived = Ranking(InsertionTetrahedra.Mode.Derived, false, out int calls, out var counts);
            Assert.That(derived, Is.EqualTo(everyRound));
            Assert.That(counts.Check.Agrees, Is.True);
            Assert.That(calls, Is.EqualTo(2), "the first round and the first derived round's check");
            Assert.That(counts.Derived, Is.EqualTo(tetrahedralised - 1));
        }

        [Test]
        public void TetrahedralisedRoundsTetrahedraliseEveryRound()
        {
            Ranking(InsertionTetrahedra.Mode.Tetrahedralised, false, out int calls, out var counts);
            Assert.That(counts.Derived, Is.EqualTo(0));
            Assert.That(counts.Tetrahedralised, Is.EqualTo(calls));
        }

        [Test]
        public void ATetrahedraliserThatBreaksTiesOtherwiseIsFollowedEveryRound()
        {
            int[] everyRound = Ranking(InsertionTetrahedra.Mode.Tetrahedralised, true, out int tetrahedralised, out _);
            int[] derived = Ranking(InsertionTetrahedra.Mode.Derived, true, out int calls, out var counts);
            Assert.That(counts.Check.Agrees, Is.False);
            Assert.That(counts.Derived, Is.EqualTo(0));
            Assert.That(counts.Check.Resyncs, Is.InRange(1, DerivationCheck.MaxResyncs), "derived rounds re-synchronised, then none derived");
            Assert.That(calls, Is.EqualTo(tetrahedralised), "every round once (the check's answer is its round's)");
            Assert.That(derived, Is.EqualTo(everyRound));
        }

        [Test]
        public void AWrongDerivationIsCaughtByTheCheck()
        {
            int[] everyRound = Ranking(InsertionTetrahedra.Mode.Tetrahedralised, false, out int tetrahedralised, out _);
            InsertionTetrahedra.AlterDerivedForTests = tets => tets.Skip(4).ToArray();  // one tetrahedron lost
            int[] derived = Ranking(InsertionTetrahedra.Mode.Derived, false, out int calls, out var counts);
            Assert.That(counts.Check.Agrees, Is.False);
            Assert.That(calls, Is.EqualTo(tetrahedralised));
            Assert.That(derived, Is.EqualTo(everyRound));
        }

        [Test]
        public void AWrongDerivationIsReplacedAndTheNextRoundDerivesAgain()
        {
            int[] everyRound = Ranking(InsertionTetrahedra.Mode.Tetrahedralised, false, out int tetrahedralised, out _);
            int derivations = 0;
            InsertionTetrahedra.AlterDerivedForTests = tets => ++derivations == 1 ? tets.Skip(4).ToArray() : tets;  // the first loses one
            int[] derived = Ranking(InsertionTetrahedra.Mode.Derived, false, out int calls, out var counts);
            Assert.That(derived, Is.EqualTo(everyRound));
            Assert.That(counts.Check.Resyncs, Is.EqualTo(1));
            Assert.That(counts.Check.Agrees, Is.True);
            Assert.That(calls, Is.EqualTo(3), "the first round, the wrong round's check (its answer), the next round's check");
            Assert.That(counts.Derived, Is.EqualTo(tetrahedralised - 2));
        }

        [Test]
        public void AFailedDerivationTetrahedralisesThatRound()
        {
            int[] everyRound = Ranking(InsertionTetrahedra.Mode.Tetrahedralised, false, out int tetrahedralised, out _);
            int failures = 0;
            // Every other derivation fails: those rounds are tetrahedralised, and the next derives from their answer.
            InsertionTetrahedra.AlterDerivedForTests = tets => ++failures % 2 == 1 ? null : tets;
            int[] derived = Ranking(InsertionTetrahedra.Mode.Derived, false, out int calls, out var counts);
            Assert.That(derived, Is.EqualTo(everyRound));
            Assert.That(counts.Check.Agrees, Is.True);
            Assert.That(counts.Derived, Is.GreaterThan(0));
            Assert.That(counts.Derived + calls, Is.EqualTo(tetrahedralised + 1), "each round derived or tetrahedralised, and one check");
        }
    }
}
