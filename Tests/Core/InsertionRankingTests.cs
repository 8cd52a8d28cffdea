using System;
using System.Collections.Generic;
using System.Linq;
using System.Numerics;
using System.Threading;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Json;
using Lpnn.Probes.Core.Quality;
using Lpnn.Probes.Core.Selection;
using Lpnn.Probes.Core.Sh;
using Lpnn.Probes.Core.Tests.Support;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    /// <summary>The insertion ranking (Documentation~/quality.md §5): parity with the Python reference through
    /// Tests/Data/insertion_golden.json (certified unique answers, Tests/Data/README.md), and its behaviour on cases
    /// whose answer is known by hand.</summary>
    [TestFixture]
    public class InsertionRankingTests
    {
        private static int[] Ints(JsonValue array) => array.Items.Select(v => (int)v.AsNumber).ToArray();

        private sealed class GoldenCase
        {
            public string Name;
            public JsonValue Json;
            public EvaluationGrid Grid;
            public ReferenceLighting Reference;
            /// <summary>The guided case's float32 scores (null: plain insertion).</summary>
            public float[] Scores;
            /// <summary>The guided case's weights, computed here from <see cref="Scores"/> and checked to equal the golden's
            /// exactly (null: plain insertion).</summary>
            public double[] Guide;

            public static List<GoldenCase> ReadAll()
            {
                var golden = TestData.ReadJson("insertion_golden.json");
                StringAssert.StartsWith("exact", golden.Get("tolerance").AsString);
                Assert.That(golden.Get("exact_threshold").AsNumber, Is.EqualTo(InsertionRanking.Exact));
                var cases = new List<GoldenCase>();
                foreach (var c in golden.Get("cases").Items)
                {
                    var grid = GoldenLighting.Grid(c);
                    float[] scores = null;
                    double[] guide = null;
                    if (c.TryGet("scores", out var scoreValues))
                    {
                        scores = JsonArrays.Floats(scoreValues);
                        Assert.That(scores.Select(v => (double)v), Is.EqualTo(JsonArrays.Doubles(scoreValues)), "the scores are float32 values");
                        guide = SpreadWeights.Compute(scores);
                        Assert.That(guide, Is.EqualTo(JsonArrays.Doubles(c.Get("guide"))), "guide weights of " + c.Get("name").AsString);
                        Assert.That(InsertionRanking.GuideWeights(scores), Is.EqualTo(guide));
                    }
                    cases.Add(new GoldenCase
                    {
                        Name = c.Get("name").AsString,
                        Json = c,
                        Grid = grid,
                        Reference = GoldenLighting.Reference(c, grid),
                        Scores = scores,
                        Guide = guide,
                    });
                }
                Assert.That(cases.Select(c => c.Name), Is.EqualTo(new[] { "enclosed", "outside", "plane", "guided", "ties" }));
                Assert.That(cases.Select(c => c.Scores != null), Is.EqualTo(new[] { false, false, false, true, false }));
                return cases;
            }
        }

        [Test]
        public void TypicalTetrahedraEqualThePythonReference()
        {
            int checkedCases = 0;
            foreach (var c in GoldenCase.ReadAll())
            {
                if (!c.Json.TryGet("typical_tetrahedron", out var expected)) continue;
                Assert.That(InsertionRanking.TypicalTetrahedron(c.Grid, c.Reference), Is.EqualTo(Ints(expected)), c.Name);
                Assert.That(InsertionRanking.Start(c.Grid, c.Reference), Is.EqualTo(Ints(c.Json.Get("start"))), c.Name);
                checkedCases++;
            }
            Assert.That(checkedCases, Is.EqualTo(3));
        }

        [Test]
        public void EveryRoundGivenItsMeshEqualsThePythonReference()
        {
            int rounds = 0, guidedRounds = 0;
            foreach (var c in GoldenCase.ReadAll())
            {
                if (!c.Json.TryGet("rounds", out var list)) continue;
                double growth = c.Json.Get("growth").AsNumber;
                foreach (var round in list.Items)
                {
                    int[] probes = Ints(round.Get("probes"));
                    int[] tetrahedra = round.Get("tetrahedra").Items.SelectMany(Ints).ToArray();
                    Assert.That(InsertionRanking.NextBatch(c.Reference, probes, tetrahedra, growth, c.Guide), Is.EqualTo(Ints(round.Get("batch"))),
                        c.Name + " round from " + probes.Length + " probes");
                    rounds++;
                    if (c.Guide != null) guidedRounds++;
                }
            }
            Assert.That(rounds, Is.GreaterThan(10));
            Assert.That(guidedRounds, Is.GreaterThan(10));
        }

        [Test]
        public void OurDelaunayFindsTheGoldenTetrahedraSoTheCellsAreUnique()
        {
            foreach (var c in GoldenCase.ReadAll())
            {
                // The ties case's lattice has no unique Delaunay tetrahedralisation: its tetrahedra are given (Python's).
                if (c.Name == "ties" || !c.Json.TryGet("rounds", out var list)) continue;
                foreach (var round in list.Items)
                {
                    int[] probes = Ints(round.Get("probes"));
                    var positions = probes.Select(p => c.Reference.GetPosition(p)).ToArray();
                    Assert.That(TetrahedronKeys(new BowyerWatsonDelaunay().Tetrahedralize(positions)),
                        Is.EqualTo(TetrahedronKeys(round.Get("tetrahedra").Items.SelectMany(Ints).ToArray())), c.Name);
                }
            }
        }

        /// <summary>Documentation~/quality.md §1 "Ties" on the golden's lattice: a point on a face, edge or vertex shared by
        /// several tetrahedra takes the lowest-index one, a point outside with several nearest hull triangles the lowest
        /// owner's, its nearest point snapped onto the edge or vertex they share. The golden's cells and weights come from the
        /// generator's brute-force enumeration in exact rationals, not from either language's locator.</summary>
        [Test]
        public void TheTiesCaseGivesEveryPointTheExactTieRulesCellAndWeights()
        {
            var c = GoldenCase.ReadAll().Single(g => g.Name == "ties");
            var round = c.Json.Get("rounds").Items.Single();
            int[] probes = Ints(round.Get("probes"));
            int[] tetrahedra = round.Get("tetrahedra").Items.SelectMany(Ints).ToArray();
            int[] cells = Ints(round.Get("cells"));
            var stencils = round.Get("stencils").Items.ToArray();
            int outside = 0, located = 0;
            for (int n = 0; n < c.Reference.Count; n++)
            {
                if (cells[n] < 0) continue;
                var stencil = PlacementError.StencilOf(c.Reference, probes, tetrahedra, n);
                Assert.That(stencil.Cell, Is.EqualTo(cells[n]), "the cell of point " + n);
                var ours = new double[probes.Length];
                ours[stencil.Probe0] += stencil.Weight0;
                ours[stencil.Probe1] += stencil.Weight1;
                ours[stencil.Probe2] += stencil.Weight2;
                ours[stencil.Probe3] += stencil.Weight3;
                var expected = new double[probes.Length];
                foreach (var pair in stencils[n].Items) expected[(int)pair.Items.First().AsNumber] = pair.Items.Last().AsNumber;
                Assert.That(ours, Is.EqualTo(expected).Within(1e-12), "the weights of point " + n);
                if (stencil.Outside) outside++;
                located++;
            }
            Assert.That(outside, Is.GreaterThan(10));
            Assert.That(located, Is.EqualTo(c.Reference.Count - probes.Length));
        }

        private static List<string> TetrahedronKeys(int[] tetrahedra)
        {
            var keys = new List<string>();
            for (int t = 0; t < tetrahedra.Length; t += 4)
            {
                var sorted = new[] { tetrahedra[t], tetrahedra[t + 1], tetrahedra[t + 2], tetrahedra[t + 3] };
                Array.Sort(sorted);
                keys.Add(string.Join(",", sorted));
            }
            keys.Sort(StringComparer.Ordinal);
            return keys;
        }

        [TestCase("enclosed")]
        [TestCase("guided")]
        public void TheWholeRankingEqualsThePythonReference(string name)
        {
            var c = GoldenCase.ReadAll().Single(g => g.Name == name);
            double growth = c.Json.Get("growth").AsNumber;
            int[] expected = Ints(c.Json.Get("ranking"));
            Assert.That(InsertionRanking.Rank(c.Grid, c.Reference, new BowyerWatsonDelaunay(), growth, scores: c.Scores), Is.EqualTo(expected));
            // The same through the order's own guide, and through the grid-level entry (all points valid).
            Assert.That(new InsertionOrder(c.Grid, c.Reference, new BowyerWatsonDelaunay(), growth, c.Guide).All(), Is.EqualTo(expected));
            // The ranking is its rounds' batches in order.
            var order = Ints(c.Json.Get("start")).ToList();
            foreach (var round in c.Json.Get("rounds").Items)
            {
                Assert.That(Ints(round.Get("probes")), Is.EqualTo(order));
                order.AddRange(Ints(round.Get("batch")));
            }
            Assert.That(expected.Take(order.Count), Is.EqualTo(order));
            if (c.Guide != null)  // the guide matters in this case: plain insertion ranks otherwise
                Assert.That(InsertionRanking.Rank(c.Grid, c.Reference, new BowyerWatsonDelaunay(), growth), Is.Not.EqualTo(expected));
        }

        /// <summary>The rounds from scratch (every point located each round, <see cref="InsertionRanking.NextBatch"/>) and
        /// incrementally (<see cref="InsertionRounds"/>, as <see cref="InsertionOrder"/> runs them) side by side: the same
        /// batch every round. Returns the whole order and how many points kept their tetrahedron.</summary>
        private static List<int> RoundsBothWays(EvaluationGrid grid, ReferenceLighting reference, double growth, double[] guide, out long kept)
        {
            var order = InsertionRanking.Start(grid, reference).ToList();
            var rounds = new InsertionRounds();
            var delaunay = new BowyerWatsonDelaunay();
            while (true)
            {
                int[] probes = order.ToArray();
                int[] tetrahedra = TetrahedronNumbering.Tetrahedralize(delaunay, reference, probes);  // numbered as the order's rounds
                int[] fresh = InsertionRanking.NextBatch(reference, probes, tetrahedra, growth, guide);
                Assert.That(rounds.NextBatch(reference, probes, tetrahedra, growth, guide, null), Is.EqualTo(fresh),
                    "round " + rounds.Rounds + " from " + probes.Length + " probes");
                if (fresh.Length == 0) break;
                order.AddRange(fresh);
            }
            Assert.That(rounds.Kept + rounds.Located, Is.GreaterThan(0));
            kept = rounds.Kept;
            return order;
        }

        [Test]
        public void IncrementalRoundsEqualRoundsFromScratchOnTheGoldenCases()
        {
            foreach (var c in GoldenCase.ReadAll())
            {
                if (!c.Json.TryGet("ranking", out var ranking)) continue;
                double growth = c.Json.Get("growth").AsNumber;
                var order = RoundsBothWays(c.Grid, c.Reference, growth, c.Guide, out long kept);
                Assert.That(kept, Is.GreaterThan(0), c.Name + ": no point kept its tetrahedron, so nothing incremental was tested");
                Assert.That(Ints(ranking).Take(order.Count), Is.EqualTo(order), c.Name);
                Assert.That(new InsertionOrder(c.Grid, c.Reference, new BowyerWatsonDelaunay(), growth, c.Guide).Prefix(order.Count).Take(order.Count),
                    Is.EqualTo(order), c.Name);
            }
        }

        [Test]
        public void IncrementalRoundsEqualRoundsFromScratchOnJitteredPoints()
        {
            var grid = QualityFixtures.Box(9, 8, 7);
            var positions = QualityFixtures.Jittered(QualityFixtures.Positions(grid), 0.2f, 11);
            var reference = ReferenceLighting.Create(positions, QualityFixtures.BlobField(positions, new Vector3(2, 2, 2), new Vector3(6, 5, 4), 2.5f));
            foreach (double growth in new[] { InsertionRanking.DefaultGrowth, 0.5 })
            {
                var order = RoundsBothWays(grid, reference, growth, null, out long kept);
                Assert.That(kept, Is.GreaterThan(grid.Count / 4), "growth " + growth + ": few points kept their tetrahedron");
                // The lazy order runs the incremental rounds: its ranking is the rounds' batches, then the rest by index.
                var rest = Enumerable.Range(0, grid.Count).Where(p => !order.Contains(p));
                Assert.That(new InsertionOrder(grid, reference, new BowyerWatsonDelaunay(), growth).All(), Is.EqualTo(order.Concat(rest)), "growth " + growth);
            }
        }

        // ---- behaviour on cases known by hand -------------------------------------------------------------------------

        /// <summary>A 4 × 4 × 3 lattice, positions jittered into general position (a unique Delaunay).</summary>
        private static EvaluationGrid Grid() => QualityFixtures.Box(4, 4, 3);

        private static Vector3[] Jittered(EvaluationGrid grid) => QualityFixtures.Jittered(QualityFixtures.Positions(grid), 0.2f, 7);

        [Test]
        public void OnAnAffineFieldTheStartReproducesEverythingAndTheRestFollowsByIndex()
        {
            var grid = Grid();
            var positions = Jittered(grid);
            var reference = ReferenceLighting.Create(positions, QualityFixtures.LinearField(positions, new Vector3(-1, -1, -1)));
            int[] ranking = InsertionRanking.Rank(grid, reference, new BowyerWatsonDelaunay());
            int[] start = InsertionRanking.TypicalTetrahedron(grid, reference);
            Assert.That(ranking.Take(start.Length), Is.EqualTo(start));
            // Inside the start's hull every point is exact, but most points lie outside it: the hull projection is not
            // affine, so insertion goes on until the hull is covered; it must still be a permutation.
            Assert.That(ranking.OrderBy(p => p), Is.EqualTo(Enumerable.Range(0, grid.Count)));
        }

        [Test]
        public void RankValidRanksTheValidPointsAloneAndPutsTheInvalidOnesLast()
        {
            var grid = Grid();
            var positions = QualityFixtures.Positions(grid);
            var sh = QualityFixtures.LinearField(positions, new Vector3(-1, -1, -1));
            var valid = new bool[grid.Count];
            for (int n = 0; n < grid.Count; n++) valid[n] = grid.GetId(n).I > 0; // the layer x = 0 is inside geometry
            double scale = ReferenceLighting.FromGrid(grid, sh).SceneScale;
            int[] ranking = InsertionRanking.RankValid(grid, sh, scale, valid, new BowyerWatsonDelaunay());
            Assert.That(ranking.OrderBy(p => p), Is.EqualTo(Enumerable.Range(0, grid.Count)));
            int validCount = valid.Count(v => v);
            Assert.That(ranking.Take(validCount).All(p => valid[p]), Is.True, "a point inside geometry was ranked among the valid ones");
            Assert.That(ranking.Skip(validCount), Is.EqualTo(Enumerable.Range(0, grid.Count).Where(p => !valid[p])));
            // The valid part is the insertion ranking of the valid sub-grid, mapped back (independent construction here).
            var rows = Enumerable.Range(0, grid.Count).Where(p => valid[p]).ToArray();
            var subGrid = grid.Subset(valid);
            var subSh = rows.SelectMany(p => sh.Skip(ShMath.FloatsPerProbe * p).Take(ShMath.FloatsPerProbe)).ToArray();
            int[] sub = InsertionRanking.Rank(subGrid, ReferenceLighting.FromGrid(subGrid, subSh, scale), new BowyerWatsonDelaunay());
            Assert.That(ranking.Take(validCount), Is.EqualTo(sub.Select(p => rows[p])));
            // No flags: the whole grid's ranking.
            Assert.That(InsertionRanking.RankValid(grid, sh, scale, null, new BowyerWatsonDelaunay()),
                        Is.EqualTo(InsertionRanking.Rank(grid, ReferenceLighting.FromGrid(grid, sh, scale), new BowyerWatsonDelaunay())));
            // Too few valid points: refused, not ranked.
            var three = new bool[grid.Count];
            three[0] = three[1] = three[2] = true;
            Assert.Throws<SelectionException>(() => InsertionRanking.RankValid(grid, sh, scale, three, new BowyerWatsonDelaunay()));
        }

        [Test]
        public void WithUniformLightingFourProbesAreExactAndTheRestFollowsByIndex()
        {
            var grid = Grid();
            var positions = Jittered(grid);
            var probe = new ShL2();
            probe.AddAmbientLight(new Vector3(0.3f, 0.2f, 0.1f));
            var sh = new float[ShMath.FloatsPerProbe * grid.Count];
            for (int n = 0; n < grid.Count; n++) probe.CopyTo(sh, ShMath.FloatsPerProbe * n);
            var reference = ReferenceLighting.Create(positions, sh);
            int[] ranking = InsertionRanking.Rank(grid, reference, new BowyerWatsonDelaunay());
            int[] typical = InsertionRanking.TypicalTetrahedron(grid, reference);
            // Every deviation is 0, so the candidates are the 5 lowest indices (ceil(0.1 × 48)), all in the bottom layer: the
            // tetrahedron guarantee adds the first point off it (16, the first of the next layer). Nothing needs fixing after.
            Assert.That(typical.Take(4).All(p => p < 5), Is.True);
            Assert.That(typical.Length, Is.EqualTo(5));
            Assert.That(typical[4], Is.EqualTo(16));
            Assert.That(new PlacementEvaluator(reference, new BowyerWatsonDelaunay()).MeanError(typical), Is.LessThan(1e-12));
            // The start adds the box's 8 corners (the extremes along ±i±j±k), those not already listed, in direction order.
            var corners = BoxCorners(grid).Distinct().Where(p => !typical.Contains(p));
            int[] start = InsertionRanking.Start(grid, reference);
            Assert.That(start, Is.EqualTo(typical.Concat(corners)));
            var rest = Enumerable.Range(0, grid.Count).Where(p => !start.Contains(p));
            Assert.That(ranking, Is.EqualTo(start.Concat(rest)));
        }

        /// <summary>A box grid's corners, independently of <see cref="InsertionRanking.ExtremePoints"/>: per direction
        /// (s_i, s_j, s_k) in the order (-,-,-), (-,-,+), …, (+,+,+), the id with the box's minimum or maximum on each axis.</summary>
        private static IEnumerable<int> BoxCorners(EvaluationGrid grid)
        {
            var ids = Enumerable.Range(0, grid.Count).Select(grid.GetId).ToArray();
            for (int d = 0; d < 8; d++)
                yield return grid.IndexOf(new LatticeId((d & 4) != 0 ? ids.Max(id => id.I) : ids.Min(id => id.I),
                                                        (d & 2) != 0 ? ids.Max(id => id.J) : ids.Min(id => id.J),
                                                        (d & 1) != 0 ? ids.Max(id => id.K) : ids.Min(id => id.K)));
        }

        [Test]
        public void ExtremePointsAreABoxsCornersAndTiesGoToTheLowerIndex()
        {
            var box = Grid();
            Assert.That(InsertionRanking.ExtremePoints(box), Is.EqualTo(BoxCorners(box).ToArray()));
            // A diamond in the plane k = 0 (and one point above): along (+,+,-) the ids (2,0,0), (1,1,0) and (0,2,0) tie at 2
            // (i + j - k), and the lowest index among them wins; every direction's value is checked against all points.
            var ids = new[] { new LatticeId(1, 0, 0), new LatticeId(0, 1, 0), new LatticeId(2, 0, 0), new LatticeId(1, 1, 0),
                              new LatticeId(0, 2, 0), new LatticeId(1, 1, 1) };
            var grid = EvaluationGrid.FromIds(1.0, ids.OrderBy(id => id).ToArray());
            int[] extremes = InsertionRanking.ExtremePoints(grid);
            Assert.That(extremes.Length, Is.EqualTo(8));
            for (int d = 0; d < 8; d++)
            {
                Func<LatticeId, long> value = id => ((d & 4) != 0 ? id.I : -id.I) + ((d & 2) != 0 ? id.J : -id.J) + ((d & 1) != 0 ? id.K : -id.K);
                long best = Enumerable.Range(0, grid.Count).Max(p => value(grid.GetId(p)));
                int first = Enumerable.Range(0, grid.Count).First(p => value(grid.GetId(p)) == best);
                Assert.That(extremes[d], Is.EqualTo(first), "direction " + d);
            }
            int tied = Enumerable.Range(0, grid.Count).Count(p => grid.GetId(p).I + grid.GetId(p).J == 2 && grid.GetId(p).K == 0);
            Assert.That(tied, Is.EqualTo(3));  // the tie this case is about exists
        }

        [Test]
        public void TheWorstPointOfAnEnclosingTetrahedronIsInsertedFirst()
        {
            // Four corners of a large tetrahedron plus interior points on an affine field: interior points are exact,
            // except one with a bump, which must come right after the corners' round.
            var grid = QualityFixtures.Box(3, 3, 3);
            int n = grid.Count;
            var positions = Jittered(grid);
            var sh = QualityFixtures.LinearField(positions, new Vector3(-1, -1, -1));
            int bumped = 13;  // the centre of the 3 × 3 × 3 box
            for (int c = 0; c < ShMath.FloatsPerProbe; c += ShMath.CoefficientsPerChannel) sh[ShMath.FloatsPerProbe * bumped + c] += 3f;
            var reference = ReferenceLighting.Create(positions, sh);
            int[] start = InsertionRanking.TypicalTetrahedron(grid, reference);
            var tetrahedralizer = new BowyerWatsonDelaunay();
            var everythingButBumped = Enumerable.Range(0, n).Where(p => p != bumped).ToArray();
            int[] tetrahedra = tetrahedralizer.Tetrahedralize(everythingButBumped.Select(p => positions[p]).ToArray());
            // From all other points, only the bumped one is wrong: it is the whole batch.
            Assert.That(InsertionRanking.NextBatch(reference, everythingButBumped, tetrahedra), Is.EqualTo(new[] { bumped }));
            Assert.That(start.Length, Is.GreaterThanOrEqualTo(4));
        }

        // ---- guided insertion (quality.md §5.2) ----------------------------------------------------------------------------

        /// <summary>One cell: the 4 corners of a large tetrahedron are the probes, 5 points inside it lie on an affine field
        /// (dyadic coordinates: exact) except points 5 and 6, which carry bumps (6 the larger); 4, 7 and 8 are exact.</summary>
        private static ReferenceLighting OneCell(out int[] probes, out int[] tetrahedra)
        {
            var positions = new[]
            {
                new Vector3(0, 0, 0), new Vector3(8, 0, 0), new Vector3(0, 8, 0), new Vector3(0, 0, 8),
                new Vector3(1, 1, 1), new Vector3(2, 1, 1), new Vector3(1, 2, 1), new Vector3(1, 1, 2), new Vector3(2, 2, 1),
            };
            var sh = QualityFixtures.LinearField(positions, new Vector3(-1, -1, -1));
            for (int c = 0; c < ShMath.FloatsPerProbe; c += ShMath.CoefficientsPerChannel)
            {
                sh[ShMath.FloatsPerProbe * 5 + c] += 1f;
                sh[ShMath.FloatsPerProbe * 6 + c] += 2f;
            }
            probes = new[] { 0, 1, 2, 3 };
            tetrahedra = new BowyerWatsonDelaunay().Tetrahedralize(positions.Take(4).ToArray());
            return ReferenceLighting.Create(positions, sh);
        }

        private static double[] Ones(int count) => Enumerable.Repeat(1.0, count).ToArray();

        [Test]
        public void TheGuidePicksAmongACellsBadlyInterpolatedPointsButNeverAnExactOne()
        {
            var reference = OneCell(out int[] probes, out int[] tetrahedra);
            int n = reference.Count;
            Assert.That(tetrahedra.Length, Is.EqualTo(4), "one cell");
            const double growth = InsertionRanking.DefaultGrowth;
            // Plain insertion, and equal weights: the cell's worst point, the larger bump.
            Assert.That(InsertionRanking.NextBatch(reference, probes, tetrahedra), Is.EqualTo(new[] { 6 }));
            Assert.That(InsertionRanking.NextBatch(reference, probes, tetrahedra, growth, Ones(n)), Is.EqualTo(new[] { 6 }));
            // A guide that rates the smaller bump ten times higher takes it instead.
            var guide = Ones(n);
            guide[5] = 10;
            Assert.That(InsertionRanking.NextBatch(reference, probes, tetrahedra, growth, guide), Is.EqualTo(new[] { 5 }));
            // Exactly interpolated points never become the candidate, however high their weight; a lower weight on the worst
            // point is only a preference among the badly interpolated ones.
            guide = Ones(n);
            guide[4] = guide[7] = guide[8] = 1e12;
            guide[6] = 1e-6;
            Assert.That(InsertionRanking.NextBatch(reference, probes, tetrahedra, growth, guide), Is.EqualTo(new[] { 5 }));
            guide[5] = 1e-9;
            Assert.That(InsertionRanking.NextBatch(reference, probes, tetrahedra, growth, guide), Is.EqualTo(new[] { 6 }));
            // A cell whose points are all exact needs no point, guided or not.
            var flat = ReferenceLighting.Create(Enumerable.Range(0, n).Select(reference.GetPosition).ToArray(),
                QualityFixtures.LinearField(Enumerable.Range(0, n).Select(reference.GetPosition).ToArray(), new Vector3(-1, -1, -1)));
            Assert.That(InsertionRanking.NextBatch(flat, probes, tetrahedra, growth, guide), Is.Empty);
        }

        [Test]
        public void EqualWeightsGiveThePlainRanking()
        {
            var grid = Grid();
            var positions = Jittered(grid);
            var reference = ReferenceLighting.Create(positions, QualityFixtures.BlobField(positions, new Vector3(1, 1, 1), new Vector3(2, 3, 1), 1.2f));
            int[] plain = InsertionRanking.Rank(grid, reference, new BowyerWatsonDelaunay());
            var equal = Enumerable.Repeat(0.37f, grid.Count).ToArray();
            Assert.That(InsertionRanking.GuideWeights(equal), Is.All.EqualTo(1.0));
            Assert.That(InsertionRanking.Rank(grid, reference, new BowyerWatsonDelaunay(), scores: equal), Is.EqualTo(plain));
            Assert.That(new InsertionOrder(grid, reference, new BowyerWatsonDelaunay(), InsertionRanking.DefaultGrowth, Ones(grid.Count)).All(), Is.EqualTo(plain));
            // Unequal scores change the ranking here (a permutation still).
            var varied = Enumerable.Range(0, grid.Count).Select(p => 0.05f + 0.9f * ((p * 37) % grid.Count) / grid.Count).ToArray();
            int[] guided = InsertionRanking.Rank(grid, reference, new BowyerWatsonDelaunay(), scores: varied);
            Assert.That(guided.OrderBy(p => p), Is.EqualTo(Enumerable.Range(0, grid.Count)));
            Assert.That(guided, Is.Not.EqualTo(plain));
        }

        [Test]
        public void RankValidWeighsTheValidPointsScoresAlone()
        {
            // `lpnn place --guided` drops the invalid points and then computes the weights: their median is the valid points'.
            var grid = QualityFixtures.Box(6, 5, 4);
            var positions = QualityFixtures.Positions(grid);
            var sh = QualityFixtures.BlobField(positions, new Vector3(2, 1, 1), new Vector3(4, 3, 2), 1.3f);
            var valid = new bool[grid.Count];
            for (int n = 0; n < grid.Count; n++) valid[n] = grid.GetId(n).I > 1; // two layers inside geometry
            var scores = new float[grid.Count];
            for (int n = 0; n < grid.Count; n++) scores[n] = valid[n] ? 0.05f + 0.9f * ((n * 53) % 97) / 97f : 0f;  // 0: as the Scoring step scatters
            double scale = ReferenceLighting.FromGrid(grid, sh).SceneScale;
            int[] ranking = InsertionRanking.RankValid(grid, sh, scale, valid, new BowyerWatsonDelaunay(), scores: scores);
            int validCount = valid.Count(v => v);
            Assert.That(ranking.OrderBy(p => p), Is.EqualTo(Enumerable.Range(0, grid.Count)));
            Assert.That(ranking.Skip(validCount), Is.EqualTo(Enumerable.Range(0, grid.Count).Where(p => !valid[p])));
            // Independent construction: the valid sub-grid ranked with the weights of its own scores, mapped back.
            var rows = Enumerable.Range(0, grid.Count).Where(p => valid[p]).ToArray();
            var subGrid = grid.Subset(valid);
            var subSh = rows.SelectMany(p => sh.Skip(ShMath.FloatsPerProbe * p).Take(ShMath.FloatsPerProbe)).ToArray();
            var subGuide = InsertionRanking.GuideWeights(rows.Select(p => scores[p]).ToArray());
            int[] sub = new InsertionOrder(subGrid, ReferenceLighting.FromGrid(subGrid, subSh, scale), new BowyerWatsonDelaunay(),
                InsertionRanking.DefaultGrowth, subGuide).All();
            Assert.That(ranking.Take(validCount), Is.EqualTo(sub.Select(p => rows[p])));
            Assert.That(ranking, Is.Not.EqualTo(InsertionRanking.RankValid(grid, sh, scale, valid, new BowyerWatsonDelaunay())), "the guide matters here");
            // The lazy order reads the same prefixes.
            var order = InsertionOrder.OfValid(grid, sh, scale, valid, new BowyerWatsonDelaunay(), InsertionRanking.DefaultGrowth, scores);
            Assert.That(order.Prefix(20).Take(20), Is.EqualTo(ranking.Take(20)));
            // No flags: the weights of every point's score.
            Assert.That(InsertionRanking.RankValid(grid, sh, scale, null, new BowyerWatsonDelaunay(), scores: scores),
                Is.EqualTo(InsertionRanking.Rank(grid, ReferenceLighting.FromGrid(grid, sh, scale), new BowyerWatsonDelaunay(), scores: scores)));
        }

        [Test]
        public void BadGuidesAreRefusedNamingTheFirstBadWeight()
        {
            var grid = Grid();
            var positions = Jittered(grid);
            var reference = ReferenceLighting.Create(positions, QualityFixtures.BlobField(positions, new Vector3(1, 1, 1), new Vector3(2, 3, 1), 1.2f));
            int n = grid.Count;
            int[] probes = InsertionRanking.TypicalTetrahedron(grid, reference);
            int[] tetrahedra = new BowyerWatsonDelaunay().Tetrahedralize(probes.Select(p => positions[p]).ToArray());
            const double growth = InsertionRanking.DefaultGrowth;

            var shortGuide = Assert.Throws<PlacementErrorException>(() => InsertionRanking.NextBatch(reference, probes, tetrahedra, growth, Ones(n - 1)));
            StringAssert.Contains("one number per point (48), got 47", shortGuide.Message);
            Assert.Throws<PlacementErrorException>(() => new InsertionOrder(grid, reference, new BowyerWatsonDelaunay(), growth, Ones(n + 1)));

            var cases = new[] { double.NaN, 0.0, -0.5, double.PositiveInfinity, double.NegativeInfinity };
            var shown = new[] { "NaN", "0", "-0.5", "Infinity", "-Infinity" };
            for (int k = 0; k < cases.Length; k++)
            {
                var guide = Ones(n);
                guide[7] = guide[30] = cases[k];
                var bad = Assert.Throws<PlacementErrorException>(() => InsertionRanking.NextBatch(reference, probes, tetrahedra, growth, guide));
                StringAssert.Contains("guide weight 7 = " + shown[k] + " must be a finite number greater than 0 (2 such weights)", bad.Message);
                StringAssert.Contains("GuideWeights(scores)", bad.Message);
                // The order refuses it before any round.
                var early = Assert.Throws<PlacementErrorException>(() => new InsertionOrder(grid, reference, new BowyerWatsonDelaunay(), growth, guide));
                StringAssert.Contains("guide weight 7 = " + shown[k], early.Message);
            }

            // Scores: one per point (NaN scores are allowed: they weigh like the floor, 1e-6).
            var fewScores = Assert.Throws<PlacementErrorException>(() => InsertionRanking.Rank(grid, reference, new BowyerWatsonDelaunay(), scores: new float[n - 1]));
            StringAssert.Contains("one score per evaluation point: got 47 scores for 48 points", fewScores.Message);
            var sh = QualityFixtures.LinearField(positions, Vector3.Zero);
            var valid = Enumerable.Range(0, n).Select(p => p % 5 != 0).ToArray();
            var manyScores = Assert.Throws<PlacementErrorException>(() => InsertionOrder.OfValid(grid, sh, 1.0, valid, new BowyerWatsonDelaunay(), growth, new float[n + 1]));
            StringAssert.Contains("one score per evaluation point", manyScores.Message);
            var nan = Enumerable.Repeat(float.NaN, n).ToArray();
            Assert.That(InsertionRanking.GuideWeights(nan), Is.All.EqualTo(1.0));
        }

        [Test]
        public void APointRepeatedInTheBatchOrAProbeCannotHappen()
        {
            var grid = Grid();
            var positions = Jittered(grid);
            var reference = ReferenceLighting.Create(positions, QualityFixtures.BlobField(positions, new Vector3(1, 1, 1), new Vector3(2, 3, 1), 1.2f));
            int[] ranking = InsertionRanking.Rank(grid, reference, new BowyerWatsonDelaunay());
            Assert.That(ranking.OrderBy(p => p), Is.EqualTo(Enumerable.Range(0, grid.Count)));
            Assert.That(InsertionRanking.Rank(grid, reference, new BowyerWatsonDelaunay()), Is.EqualTo(ranking), "deterministic");
            // A larger growth inserts more per round but still ranks every point once.
            int[] fast = InsertionRanking.Rank(grid, reference, new BowyerWatsonDelaunay(), 0.5);
            Assert.That(fast.OrderBy(p => p), Is.EqualTo(Enumerable.Range(0, grid.Count)));
        }

        [Test]
        public void ProgressIsReportedAndCancellationStopsBetweenRounds()
        {
            var grid = Grid();
            var positions = Jittered(grid);
            var reference = ReferenceLighting.Create(positions, QualityFixtures.BlobField(positions, new Vector3(1, 1, 1), new Vector3(2, 3, 1), 1.2f));
            var reported = new List<long>();
            InsertionRanking.Rank(grid, reference, new BowyerWatsonDelaunay(), InsertionRanking.DefaultGrowth, (stage, done, total) =>
            {
                Assert.That(total, Is.EqualTo(grid.Count));
                reported.Add(done);
            });
            Assert.That(reported.Count, Is.GreaterThan(2));
            Assert.That(reported, Is.Ordered);
            Assert.That(reported.Last(), Is.EqualTo(grid.Count));

            using (var source = new CancellationTokenSource())
            {
                int rounds = 0;
                Assert.Throws<OperationCanceledException>(() => InsertionRanking.Rank(grid, reference, new BowyerWatsonDelaunay(), 0.1,
                    (stage, done, total) => { if (++rounds == 2) source.Cancel(); }, source.Token));
                Assert.That(rounds, Is.EqualTo(2));
            }
        }

        [Test]
        public void DegenerateInputsAreRefusedWithMessagesThatSayWhatToDo()
        {
            var grid = Grid();
            var positions = Jittered(grid);
            var reference = ReferenceLighting.Create(positions, QualityFixtures.LinearField(positions, Vector3.Zero));

            var small = QualityFixtures.Box(3, 1, 1);
            var smallReference = ReferenceLighting.Create(QualityFixtures.Positions(small), new float[ShMath.FloatsPerProbe * 3]);
            var tooFew = Assert.Throws<PlacementErrorException>(() => InsertionRanking.TypicalTetrahedron(small, smallReference));
            StringAssert.Contains("at least 4 evaluation points", tooFew.Message);

            var mismatch = Assert.Throws<PlacementErrorException>(() => InsertionRanking.Rank(QualityFixtures.Box(4, 4, 2), reference, new BowyerWatsonDelaunay()));
            StringAssert.Contains("sample the lighting for this grid", mismatch.Message);

            foreach (double growth in new[] { 0.0, -0.1, double.NaN, double.PositiveInfinity })
            {
                var bad = Assert.Throws<PlacementErrorException>(() => InsertionRanking.Rank(grid, reference, new BowyerWatsonDelaunay(), growth));
                StringAssert.Contains("growth", bad.Message);
            }

            var flat = QualityFixtures.Box(4, 4, 1);
            var flatPositions = QualityFixtures.Positions(flat);
            var flatReference = ReferenceLighting.Create(flatPositions, QualityFixtures.LinearField(flatPositions, Vector3.Zero));
            var plane = Assert.Throws<SelectionException>(() => InsertionRanking.Rank(flat, flatReference, new BowyerWatsonDelaunay()));
            StringAssert.Contains("two cells deep", plane.Message);

            var sh = QualityFixtures.LinearField(positions, Vector3.Zero);
            sh[5] = float.NaN;
            var nan = Assert.Throws<PlacementErrorException>(() => ReferenceLighting.Create(positions, sh));
            StringAssert.Contains("not finite", nan.Message);

            Assert.Throws<ArgumentNullException>(() => InsertionRanking.Rank(grid, reference, null));
        }

        [Test]
        public void TheGuideIsUsedUpToTheGuidedPointLimitAndPlainInsertionAbove()
        {
            // quality.md §5.2 (Python's insertion.guide_of): larger clouds than the network saw get no guide.
            Assert.That(InsertionRanking.GuidedPointLimit, Is.EqualTo(32768));
            var atLimit = Enumerable.Repeat(0.5f, InsertionRanking.GuidedPointLimit).ToArray();
            Assert.That(InsertionRanking.GuideOf(atLimit, atLimit.Length), Is.All.EqualTo(1.0));
            var above = Enumerable.Repeat(0.5f, InsertionRanking.GuidedPointLimit + 1).ToArray();
            Assert.That(InsertionRanking.GuideOf(above, above.Length), Is.Null);
            Assert.That(InsertionRanking.GuideOf(null, 10), Is.Null);
        }

        // ---- the method choice ---------------------------------------------------------------------------------------

        [Test]
        public void TheDefaultMethodIsRefinedInsertionAndWhatEachMethodNeeds()
        {
            // Documentation~/benchmarks.md "The speed/accuracy trade, every method": on the validation crops, once refined in batches, plain insertion keeps fewer
            // probes at τ (the default policy) than guided insertion (1.01× against 1.04× the reference's).
            Assert.That(PlacementMethods.Default, Is.EqualTo(PlacementMethod.InsertionRefined));
            Assert.That(PlacementMethods.NeedsScores(PlacementMethod.Network), Is.True);
            Assert.That(PlacementMethods.NeedsScores(PlacementMethod.Insertion), Is.False);
            Assert.That(PlacementMethods.NeedsScores(PlacementMethod.InsertionRefined), Is.False);
            Assert.That(PlacementMethods.NeedsScores(PlacementMethod.GuidedInsertion), Is.True, "the scores are its guide");
            Assert.That(PlacementMethods.NeedsScores(PlacementMethod.GuidedInsertionRefined), Is.True, "the scores are its guide");
            Assert.That(PlacementMethods.RanksByInsertion(PlacementMethod.Network), Is.False);
            Assert.That(PlacementMethods.RanksByInsertion(PlacementMethod.Insertion), Is.True);
            Assert.That(PlacementMethods.RanksByInsertion(PlacementMethod.InsertionRefined), Is.True);
            Assert.That(PlacementMethods.RanksByInsertion(PlacementMethod.GuidedInsertion), Is.True);
            Assert.That(PlacementMethods.RanksByInsertion(PlacementMethod.GuidedInsertionRefined), Is.True);
            Assert.That(Enum.GetValues(typeof(PlacementMethod)).Cast<PlacementMethod>().Where(PlacementMethods.GuidesInsertion),
                Is.EqualTo(new[] { PlacementMethod.GuidedInsertion, PlacementMethod.GuidedInsertionRefined }));
            Assert.That(Enum.GetValues(typeof(PlacementMethod)).Cast<PlacementMethod>().Where(PlacementMethods.RefinesInBatches),
                Is.EqualTo(new[] { PlacementMethod.InsertionRefined, PlacementMethod.GuidedInsertionRefined }));
            // Stored in scenes: values never move, new ones are appended.
            Assert.That((int)PlacementMethod.Network, Is.EqualTo(0));
            Assert.That((int)PlacementMethod.Insertion, Is.EqualTo(1));
            Assert.That((int)PlacementMethod.GuidedInsertion, Is.EqualTo(2));
            Assert.That((int)PlacementMethod.InsertionRefined, Is.EqualTo(3));
            Assert.That((int)PlacementMethod.GuidedInsertionRefined, Is.EqualTo(4));
            Assert.That(Enum.GetValues(typeof(PlacementMethod)).Length, Is.EqualTo(5));
        }

        [Test]
        public void PoliciesOverARankingKeepItsPrefixesAndTheToleranceSearchUsesIt()
        {
            var grid = Grid();
            var positions = Jittered(grid);
            var reference = ReferenceLighting.Create(positions, QualityFixtures.BlobField(positions, new Vector3(1, 1, 1), new Vector3(2, 3, 1), 1.2f));
            var tetrahedralizer = new BowyerWatsonDelaunay();
            int[] ranking = InsertionRanking.Rank(grid, reference, tetrahedralizer);

            var budget = ProbeSelector.SelectFromRanking(grid, ranking, SelectionSettings.Budget(10), null);
            Assert.That(budget.Indices, Is.EqualTo(ranking.Take(10).OrderBy(p => p)));
            var spread = ProbeSelector.SelectFromRanking(grid, ranking, SelectionSettings.Spread(10), null);
            Assert.That(spread.Indices, Is.EqualTo(budget.Indices));
            var percentile = ProbeSelector.SelectFromRanking(grid, ranking, SelectionSettings.Percentile(0.75), null);
            Assert.That(percentile.Indices, Is.EqualTo(ranking.Take(12).OrderBy(p => p)));

            var measure = new PlacementEvaluator(reference, tetrahedralizer);
            var tolerance = ProbeSelector.SelectFromRanking(grid, ranking, SelectionSettings.Tolerance(0.02), measure);
            Assert.That(tolerance.Tolerance.MeanError, Is.LessThanOrEqualTo(0.02));
            Assert.That(tolerance.Indices, Is.EqualTo(ranking.Take(tolerance.Tolerance.Count).OrderBy(p => p)));
            Assert.That(measure.MeanError(tolerance.Indices), Is.EqualTo(tolerance.Tolerance.MeanError));

            var threshold = Assert.Throws<SelectionException>(() => ProbeSelector.SelectFromRanking(grid, ranking, SelectionSettings.Threshold(0.5), null));
            StringAssert.Contains("needs the network's scores", threshold.Message);
            Assert.Throws<SelectionException>(() => ProbeSelector.SelectFromRanking(grid, ranking.Take(5).ToArray(), SelectionSettings.Budget(3), null));
        }

        [Test]
        public void TheLazyOrderSelectsWhatTheWholeRankingSelectsWithFewerRounds()
        {
            var grid = QualityFixtures.Box(9, 8, 6);
            var positions = QualityFixtures.Positions(grid);
            var sh = QualityFixtures.BlobField(positions, new Vector3(2, 2, 1), new Vector3(6, 5, 4), 1.5f);
            var valid = new bool[grid.Count];
            for (int n = 0; n < grid.Count; n++) valid[n] = grid.GetId(n).I > 0; // the layer x = 0 is inside geometry
            double scale = ReferenceLighting.FromGrid(grid, sh).SceneScale;
            var measure = new PlacementEvaluator(ReferenceLighting.FromGrid(grid, sh, scale), new BowyerWatsonDelaunay());
            int[] full = InsertionRanking.RankValid(grid, sh, scale, valid, new BowyerWatsonDelaunay());
            var everything = InsertionOrder.OfValid(grid, sh, scale, valid, new BowyerWatsonDelaunay());
            everything.All();
            Assert.That(everything.IsComplete, Is.True);

            var cases = new[]
            {
                SelectionSettings.Budget(20), SelectionSettings.Budget(2), SelectionSettings.Spread(30, true), SelectionSettings.Percentile(0.95),
                SelectionSettings.Tolerance(0.05), SelectionSettings.Tolerance(0.02, true),
            };
            foreach (var settings in cases)
            {
                var order = InsertionOrder.OfValid(grid, sh, scale, valid, new BowyerWatsonDelaunay());
                var lazy = ProbeSelector.SelectFromPrefixes(grid, order.Count, k => order.Prefix(k), settings, measure, valid);
                var eager = ProbeSelector.SelectFromRanking(grid, full, settings, measure, valid);
                string label = settings.Policy + " " + settings.Value;
                Assert.That(lazy.Indices, Is.EqualTo(eager.Indices), label);
                Assert.That(lazy.CornersAdded, Is.EqualTo(eager.CornersAdded), label);
                Assert.That(lazy.AddedForTetrahedron, Is.EqualTo(eager.AddedForTetrahedron), label);
                Assert.That(lazy.Indices.All(p => valid[p]), Is.True, label);
                if (settings.Policy == SelectionPolicy.Tolerance) Assert.That(lazy.Tolerance.Count, Is.EqualTo(eager.Tolerance.Count), label);
                Assert.That(order.Rounds, Is.LessThan(everything.Rounds), label + ": the lazy order ran every round");
            }
            // The prefixes are the whole ranking's.
            var stepwise = InsertionOrder.OfValid(grid, sh, scale, valid, new BowyerWatsonDelaunay());
            foreach (int k in new[] { 1, 4, 17, 60, 200, stepwise.Count })
                Assert.That(stepwise.Prefix(k).Take(k), Is.EqualTo(full.Take(k)), "prefix " + k);
        }

        [Test]
        public void APrefixThatBreaksItsContractIsRefused()
        {
            var grid = Grid();
            var positions = QualityFixtures.Positions(grid);
            var sh = QualityFixtures.LinearField(positions, new Vector3(-1, -1, -1));
            int[] ranking = InsertionRanking.RankValid(grid, sh, ReferenceLighting.FromGrid(grid, sh).SceneScale, null, new BowyerWatsonDelaunay());
            var tooShort = Assert.Throws<SelectionException>(() =>
                ProbeSelector.SelectFromPrefixes(grid, grid.Count, k => ranking.Take(k - 1).ToArray(), SelectionSettings.Budget(10), null));
            StringAssert.Contains("prefix for 10 points has 9", tooShort.Message);
            var twice = ranking.ToArray();
            twice[3] = twice[0];
            Assert.Throws<SelectionException>(() => ProbeSelector.SelectFromPrefixes(grid, grid.Count, k => twice, SelectionSettings.Budget(10), null));
            Assert.Throws<SelectionException>(() => ProbeSelector.SelectFromPrefixes(grid, grid.Count - 1, k => ranking, SelectionSettings.Budget(10), null));
        }
    }
}
