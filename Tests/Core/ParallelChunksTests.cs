using System;
using System.Collections.Generic;
using System.Linq;
using System.Numerics;
using System.Threading;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Quality;
using Lpnn.Probes.Core.Tests.Support;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    /// <summary>The per-point passes run on every core (<see cref="ParallelChunks"/>, Documentation~/benchmarks.md "The C#
    /// core under Mono"): every split of the points gives the serial answers bit for bit — stencils, errors, sums, ties —
    /// and the rays are cast on the calling thread only.</summary>
    [TestFixture]
    public class ParallelChunksTests
    {
        /// <summary>The splits compared with the serial pass (1 chunk): even, uneven and many small chunks.</summary>
        private static readonly int[] Splits = { 2, 7, 13 };

        [TearDown]
        public void Serial() => ParallelChunks.ForcedChunks = 0;

        private static T WithChunks<T>(int chunks, Func<T> run)
        {
            ParallelChunks.ForcedChunks = chunks;
            try
            {
                return run();
            }
            finally
            {
                ParallelChunks.ForcedChunks = 0;
            }
        }

        [Test]
        public void EveryIndexIsVisitedOnceWhateverTheSplit()
        {
            foreach (int count in new[] { 0, 1, 5, 4096, 4097, 100003 })
            foreach (int chunks in new[] { 0, 1, 2, 3, 7, 4097, 200000 })
            {
                var visits = new int[count];
                int calls = 0;
                ParallelChunks.ForcedChunks = chunks;
                ParallelChunks.For(count, (start, end) =>
                {
                    Interlocked.Increment(ref calls);
                    for (int i = start; i < end; i++) Interlocked.Increment(ref visits[i]);
                });
                ParallelChunks.ForcedChunks = 0;
                Assert.That(visits.All(v => v == 1), Is.True, count + " indices in " + chunks + " chunks");
                if (chunks > 0 && count > 0) Assert.That(calls, Is.EqualTo(Math.Min(chunks, count)), count + " indices in " + chunks + " chunks");
            }
        }

        /// <summary>Three of four chunks throw, at the same time or not: the lowest one's exception comes out, unwrapped, every
        /// time (a serial loop would have met it first).</summary>
        [Test]
        public void TheLowestChunksExceptionIsRethrownAsItWasThrown()
        {
            for (int attempt = 0; attempt < 20; attempt++)
            {
                ParallelChunks.ForcedChunks = 4;
                var error = Assert.Throws<PlacementErrorException>(() => ParallelChunks.For(1000, (start, end) =>
                {
                    Thread.Sleep(1);  // let the chunks overlap
                    if (start > 0) throw new PlacementErrorException("chunk at " + start);
                }));
                Assert.That(error.Message, Is.EqualTo("chunk at 250"), "attempt " + attempt);
            }
        }

        /// <summary>20 × 17 × 16 lattice points (5,440) and the 7 × 6 × 6 probes of its stride-3 sub-lattice with Kuhn
        /// tetrahedra: the points at x = 19 and y = 16 lie outside the hull (nearest hull points on shared edges and
        /// corners: hull ties), and inside, lattice points on the tetrahedra's shared faces, edges and the cubes' diagonals
        /// (location ties). Lighting: two blobs, so the errors differ from point to point.</summary>
        private sealed class Scene
        {
            public readonly EvaluationGrid Grid = QualityFixtures.Box(20, 17, 16);
            public readonly ReferenceLighting Reference;
            public readonly int[] Probes;
            public readonly int[] Tetrahedra;

            public Scene()
            {
                var positions = QualityFixtures.Positions(Grid);
                Reference = ReferenceLighting.Create(positions, QualityFixtures.BlobField(positions, new Vector3(4, 5, 3), new Vector3(14, 11, 12), 4f));
                Probes = QualityFixtures.LatticeProbes(Grid, 3);
                Tetrahedra = QualityFixtures.KuhnTetrahedra(7, 6, 6);
            }
        }

        private static Scene scene;
        private static Scene TheScene => scene ?? (scene = new Scene());

        [Test]
        public void EverySplitGivesEachPointTheStencilOfItsOwnLocation()
        {
            var s = TheScene;
            var others = Enumerable.Range(0, s.Reference.Count).Except(s.Probes).ToArray();
            var serial = Stencils(1, out List<int> serialPoints);
            Assert.That(serialPoints, Is.EqualTo(others), "every other point once, in ascending order");
            int outside = serial.Count(t => t.Outside);
            int onBoundaries = serial.Count(t => !t.Outside && Math.Min(Math.Min(t.Weight0, t.Weight1), Math.Min(t.Weight2, t.Weight3)) == 0);
            Assert.That(outside, Is.GreaterThan(500), "points outside the hull");
            Assert.That(onBoundaries, Is.GreaterThan(1000), "points on a face, edge or vertex shared by several tetrahedra");
            // The serial pass against each point located alone (a mesh each: every 11th point).
            for (int i = 0; i < others.Length; i += 11)
                Assert.That(serial[i], Is.EqualTo(PlacementError.StencilOf(s.Reference, s.Probes, s.Tetrahedra, others[i])), "point " + others[i]);
            foreach (int chunks in Splits)
            {
                Assert.That(Stencils(chunks, out List<int> points), Is.EqualTo(serial), chunks + " chunks");
                Assert.That(points, Is.EqualTo(others), chunks + " chunks");
            }
        }

        /// <summary>The stencils of every point that is not a probe, in <paramref name="chunks"/> chunks, in the order visited.</summary>
        private static List<Stencil> Stencils(int chunks, out List<int> points)
        {
            var s = TheScene;
            var visited = new List<int>();
            var stencils = new List<Stencil>();
            WithChunks(chunks, () =>
            {
                PlacementError.InterpolateOthers(s.Reference, s.Probes, s.Tetrahedra, null, (int n, ref Stencil stencil) =>
                {
                    visited.Add(n);
                    stencils.Add(stencil);
                });
                return 0;
            });
            points = visited;
            return stencils;
        }

        [Test]
        public void EverySplitGivesTheSerialErrors()
        {
            var s = TheScene;
            var serial = WithChunks(1, () => PlacementError.Evaluate(s.Reference, s.Probes, s.Tetrahedra));
            Assert.That(serial.OutsidePoints, Is.GreaterThan(500));
            Assert.That(serial.PointIrradiance.Count(e => e > 0), Is.GreaterThan(s.Reference.Count / 2), "errors to compare");
            foreach (int chunks in Splits)
            {
                var split = WithChunks(chunks, () => PlacementError.Evaluate(s.Reference, s.Probes, s.Tetrahedra));
                Assert.That(split.PointIrradiance, Is.EqualTo(serial.PointIrradiance), chunks + " chunks");
                Assert.That(split.PointSmape, Is.EqualTo(serial.PointSmape), chunks + " chunks");
                Assert.That(split.OutsidePoints, Is.EqualTo(serial.OutsidePoints), chunks + " chunks");
                Assert.That(split.Irradiance.Mean, Is.EqualTo(serial.Irradiance.Mean), chunks + " chunks");
            }
        }

        /// <summary>Three insertion rounds, from scratch and incrementally (their points kept in their tetrahedron, then the
        /// others located: two parallel passes), and the cells' sums and ties that choose each batch.</summary>
        [Test]
        public void EverySplitGivesTheSerialInsertionRounds()
        {
            var serial = Rounds(1);
            Assert.That(serial.All(b => b.Length > 0), Is.True);
            foreach (int chunks in Splits) Assert.That(Rounds(chunks), Is.EqualTo(serial), chunks + " chunks");
        }

        /// <summary>Three insertion rounds in <paramref name="chunks"/> chunks, from scratch and incrementally (the points kept
        /// in their tetrahedron, then the others located: two parallel passes), each choosing its batch from the cells'
        /// sums and ties.</summary>
        private static List<int[]> Rounds(int chunks) => WithChunks(chunks, () =>
        {
            var s = TheScene;
            var delaunay = new BowyerWatsonDelaunay();
            var batches = new List<int[]>();
            var rounds = new InsertionRounds();
            var probes = s.Probes.ToList();
            for (int round = 0; round < 3; round++)
            {
                int[] tetrahedra = round == 0 ? s.Tetrahedra : delaunay.Tetrahedralize(probes.Select(p => s.Reference.GetPosition(p)).ToArray());
                int[] fresh = InsertionRanking.NextBatch(s.Reference, probes.ToArray(), tetrahedra, 0.2);
                Assert.That(rounds.NextBatch(s.Reference, probes.ToArray(), tetrahedra, 0.2, null, null), Is.EqualTo(fresh), "round " + round);
                batches.Add(fresh);
                probes.AddRange(fresh);
            }
            Assert.That(rounds.Kept, Is.GreaterThan(0), "points kept their tetrahedron");
            return batches;
        });

        /// <summary>The refinement's seed and a trial, leak-weighted (the stencils' segments cast after the pass): the same
        /// errors, owners, sums and costs; every ray cast on the calling thread.</summary>
        [Test]
        public void EverySplitGivesTheSerialRefinementStateAndCastsOnTheCallingThread()
        {
            var s = TheScene;
            var wall = new AnalyticBoxRaycaster();
            wall.Boxes.Add(new AxisBox(new Double3(9.4, -1, -1), new Double3(9.6, 10, 20)));
            var rays = new CallingThreadRaycaster(wall);
            int[] probes = s.Probes.OrderBy(p => p).ToArray();
            int[] candidates = probes.Where((p, k) => k % 17 == 5).ToArray();
            var serial = Seed(1, probes, candidates, rays, out double[] serialCost);
            var plain = PlacementError.Evaluate(s.Reference, probes,
                new BowyerWatsonDelaunay().Tetrahedralize(probes.Select(s.Reference.GetPosition).ToArray()));
            Assert.That(Enumerable.Range(0, s.Reference.Count).Count(p => serial.Errors[p] != plain.PointIrradiance[p]), Is.GreaterThan(0),
                "some points leak through the wall (their errors weighted)");
            Assert.That(candidates.Count(c => serialCost[c] != 0), Is.GreaterThan(0));
            foreach (int chunks in Splits)
            {
                var split = Seed(chunks, probes, candidates, rays, out double[] cost);
                Assert.That(split.Errors, Is.EqualTo(serial.Errors), chunks + " chunks");
                Assert.That(split.Owners, Is.EqualTo(serial.Owners), chunks + " chunks");
                Assert.That(split.Touched, Is.EqualTo(serial.Touched), chunks + " chunks");
                Assert.That(split.ErrorSum, Is.EqualTo(serial.ErrorSum), chunks + " chunks");
                Assert.That(cost, Is.EqualTo(serialCost), chunks + " chunks");
            }
            Assert.That(rays.Casts, Is.GreaterThan(0));
            Assert.That(rays.ElsewhereCasts, Is.EqualTo(0), "rays cast from another thread than the caller's (Unity's physics runs on the main thread)");
        }

        /// <summary>The leak-weighted seed state of <paramref name="probes"/> and the removal costs of <paramref name="candidates"/>
        /// (the trial tetrahedralised, not refilled), in <paramref name="chunks"/> chunks.</summary>
        private static BatchedRefinementState Seed(int chunks, int[] probes, int[] candidates, IRaycaster rays, out double[] cost)
        {
            var s = TheScene;
            var tetrahedralizer = new BowyerWatsonDelaunay();
            int[] remaining = BatchedRefinementState.ProbesWithout(probes, candidates, s.Reference.Count);
            var costs = new double[s.Reference.Count];
            cost = costs;
            return WithChunks(chunks, () =>
            {
                BatchedRefinementState.ForceTetrahedralisation = true;
                try
                {
                    var seed = BatchedRefinementState.Evaluate(s.Reference, tetrahedralizer, probes, new LeakWeighting(rays, 3.0));
                    seed.RemovalCosts(s.Reference, tetrahedralizer, remaining, candidates, costs);
                    return seed;
                }
                finally
                {
                    BatchedRefinementState.ForceTetrahedralisation = false;
                }
            });
        }

        /// <summary>Counts the casts made from a thread other than the one that created it.</summary>
        private sealed class CallingThreadRaycaster : IRaycaster
        {
            private readonly IRaycaster _inner;
            private readonly int _thread = Thread.CurrentThread.ManagedThreadId;
            public int Casts, ElsewhereCasts;

            public CallingThreadRaycaster(IRaycaster inner) => _inner = inner;

            public void Cast(Vector3[] origins, Vector3[] directions, float maxDistance, RayHit[] results)
            {
                Interlocked.Increment(ref Casts);
                if (Thread.CurrentThread.ManagedThreadId != _thread) Interlocked.Increment(ref ElsewhereCasts);
                _inner.Cast(origins, directions, maxDistance, results);
            }
        }
    }
}
