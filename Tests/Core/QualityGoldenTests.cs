using System;
using System.Collections.Generic;
using System.Linq;
using System.Numerics;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Json;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Quality;
using Lpnn.Probes.Core.Selection;
using Lpnn.Probes.Core.Tests.Support;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    /// <summary>Parity with the Python reference (Tests/Data/README.md): spread_golden.json (rankings, index for index)
    /// and placement_error_golden.json (per-point errors and stencils on the golden's own tetrahedra, summaries, and the
    /// tolerance search with a real tetrahedraliser).</summary>
    [TestFixture]
    public class QualityGoldenTests
    {
        private static float[] FloatTriples(JsonValue rows)
        {
            var values = new float[3 * rows.Items.Count];
            for (int r = 0; r < rows.Items.Count; r++)
                for (int c = 0; c < 3; c++) values[3 * r + c] = (float)rows.Items[r].Items[c].AsNumber;
            return values;
        }

        private static Vector3[] Vectors(JsonValue rows)
        {
            float[] flat = FloatTriples(rows);
            var result = new Vector3[rows.Items.Count];
            for (int r = 0; r < result.Length; r++) result[r] = new Vector3(flat[3 * r], flat[3 * r + 1], flat[3 * r + 2]);
            return result;
        }

        /// <summary>float32 values as exact doubles; null is NaN (README).</summary>
        private static float[] Scores(JsonValue array) => array.Items.Select(v => v.IsNull ? float.NaN : (float)v.AsNumber).ToArray();

        private static int[] Ints(JsonValue array) => array.Items.Select(v => (int)v.AsNumber).ToArray();

        private static int[] Flatten(JsonValue rows) => rows.Items.SelectMany(Ints).ToArray();

        [Test]
        public void SpreadRankingsAreEqualIndexForIndex()
        {
            var golden = TestData.ReadJson("spread_golden.json");
            StringAssert.StartsWith("exact", golden.Get("tolerance").AsString);
            int cases = 0;
            foreach (var c in golden.Get("cases").Items)
            {
                string name = c.Get("name").AsString;
                Assert.That(c.Get("exponent").AsNumber, Is.EqualTo(0.5), name + ": the ranking implements the documented exponent 0.5");
                int[] expected = Ints(c.Get("ranking"));
                int[] actual = SpreadRanking.Rank(FloatTriples(c.Get("positions")), Scores(c.Get("scores")), int.MaxValue);
                Assert.That(actual, Is.EqualTo(expected), name);
                cases++;
            }
            Assert.That(cases, Is.EqualTo(7));
        }

        private sealed class PlacementGolden
        {
            public JsonValue Json;
            public Tolerance Errors, Weights;
            public ReferenceLighting Reference;
            public int[] Probes, Tetrahedra;

            public static PlacementGolden Read()
            {
                var json = TestData.ReadJson("placement_error_golden.json");
                var positions = Vectors(json.Get("positions"));
                var sh = json.Get("sh").Items.SelectMany(row => JsonArrays.Floats(row)).ToArray();
                var weights = json.Get("weights_tolerance");
                return new PlacementGolden
                {
                    Json = json,
                    Errors = Tolerance.FromJson(json),
                    Weights = new Tolerance(weights.Get("abs").AsNumber, weights.Get("rel").AsNumber),
                    Reference = ReferenceLighting.Create(positions, sh),
                    Probes = Ints(json.Get("probes")),
                    Tetrahedra = Flatten(json.Get("tetrahedra")),
                };
            }
        }

        [Test]
        public void PlacementErrorsMatchPointForPoint()
        {
            var g = PlacementGolden.Read();
            Assert.That(PointErrorMetrics.Epsilon, Is.EqualTo(g.Json.Get("epsilon").AsNumber));
            g.Errors.AssertClose(g.Json.Get("lighting_scale").AsNumber, g.Reference.SceneScale, "scene scale");
            var result = PlacementError.Evaluate(g.Reference, g.Probes, g.Tetrahedra);
            var points = g.Json.Get("points").Items;
            Assert.That(points.Count, Is.EqualTo(g.Reference.Count));
            int outside = 0;
            foreach (var point in points)
            {
                int n = (int)point.Get("index").AsNumber;
                g.Errors.AssertClose(point.Get("irradiance").AsNumber, result.PointIrradiance[n], "irradiance of point " + n);
                g.Errors.AssertClose(point.Get("smape").AsNumber, result.PointSmape[n], "smape of point " + n);
                if (point.Has("outside") && point.Get("outside").AsBoolean) outside++;
            }
            Assert.That(result.OutsidePoints, Is.EqualTo(outside));
            Assert.That(outside, Is.EqualTo(41), "README: 41 evaluation points lie outside the probes' hull");
            foreach (string metric in new[] { "irradiance", "smape" })
            {
                var expected = g.Json.Get(metric);
                var actual = metric == "irradiance" ? result.Irradiance : result.Smape;
                g.Errors.AssertClose(expected.Get("mean").AsNumber, actual.Mean, metric + " mean");
                g.Errors.AssertClose(expected.Get("p95").AsNumber, actual.P95, metric + " p95");
            }
        }

        [Test]
        public void StencilsGiveEveryProbeTheSameWeight()
        {
            // Compared per probe (weights of one probe summed), so an edge or vertex nearest point may come from either
            // of its triangles (README): only the blend has to agree.
            var g = PlacementGolden.Read();
            var hull = new HashSet<string>(g.Json.Get("hull_triangles").Items.Select(t => string.Join(",", Ints(t).OrderBy(i => i))));
            foreach (var point in g.Json.Get("points").Items)
            {
                if (point.Has("probe")) continue;
                int n = (int)point.Get("index").AsNumber;
                var s = PlacementError.StencilOf(g.Reference, g.Probes, g.Tetrahedra, n);
                Assert.That(s.Outside, Is.EqualTo(point.Get("outside").AsBoolean), "outside flag of point " + n);
                var actual = new Dictionary<int, double>();
                Add(actual, s.Probe0, s.Weight0);
                Add(actual, s.Probe1, s.Weight1);
                Add(actual, s.Probe2, s.Weight2);
                Add(actual, s.Probe3, s.Weight3);
                var expected = new Dictionary<int, double>();
                int[] vertices = Ints(point.Get("stencil"));
                double[] weights = JsonArrays.Doubles(point.Get("weights"));
                for (int k = 0; k < 4; k++) Add(expected, vertices[k], weights[k]);
                foreach (int probe in expected.Keys.Union(actual.Keys))
                {
                    double e, a;
                    expected.TryGetValue(probe, out e);
                    actual.TryGetValue(probe, out a);
                    g.Weights.AssertClose(e, a, "weight of probe " + probe + " at point " + n);
                }
                if (s.Outside)
                {
                    var used = actual.Where(kv => kv.Value > 0).Select(kv => kv.Key).OrderBy(i => i).ToArray();
                    Assert.That(hull.Any(t => used.All(v => t.Split(',').Contains(v.ToString()))), "point " + n + " is interpolated on a hull triangle");
                }
            }
        }

        private static void Add(Dictionary<int, double> weights, int probe, double weight)
        {
            weights.TryGetValue(probe, out double sum);
            weights[probe] = sum + weight;
        }

        [Test]
        public void TheToleranceSearchChecksTheSameCountsAndFindsTheSameAnswer()
        {
            var g = PlacementGolden.Read();
            var policy = g.Json.Get("tolerance_policy");
            float[] positions = FloatTriples(g.Json.Get("positions"));
            float[] scores = Scores(policy.Get("scores"));
            int[] ranking = SpreadRanking.Rank(positions, scores, int.MaxValue);
            Assert.That(ranking, Is.EqualTo(Ints(policy.Get("ranking"))), "spread ranking of the policy's scores");

            // README: 80 points of a 5 × 4 × 4 lattice (cell 1 m), in grid order, jittered; the guarantee reads lattice ids.
            var ids = new List<LatticeId>();
            for (int k = 0; k < 4; k++)
                for (int j = 0; j < 4; j++)
                    for (int i = 0; i < 5; i++) ids.Add(new LatticeId(i, j, k));
            var grid = EvaluationGrid.FromIds(1.0, ids);
            var result = TolerancePolicy.Place(grid, ranking, g.Reference, new BowyerWatsonDelaunay(), policy.Get("tolerance").AsNumber);

            var expected = policy.Get("checked").Items;
            var checkedCounts = result.Tolerance.Evaluated;
            Assert.That(checkedCounts.Select(e => e.Key).ToArray(), Is.EqualTo(expected.Select(e => (int)e.Get("count").AsNumber).ToArray()), "counts evaluated");
            for (int c = 0; c < expected.Count; c++)
                g.Errors.AssertClose(expected[c].Get("mean_error").AsNumber, checkedCounts[c].Value, "mean error of prefix " + checkedCounts[c].Key);
            Assert.That(result.Tolerance.Count, Is.EqualTo((int)policy.Get("count").AsNumber));
            g.Errors.AssertClose(policy.Get("mean_error").AsNumber, result.Tolerance.MeanError, "mean error of the answer");
            Assert.That(result.AddedForTetrahedron, Is.EqualTo(0));
            Assert.That(result.Indices, Is.EqualTo(ranking.Take(result.Tolerance.Count).OrderBy(i => i).ToArray()));
            double largest = 0;
            for (int c = 0; c < expected.Count; c++) largest = Math.Max(largest, Math.Abs(expected[c].Get("mean_error").AsNumber - checkedCounts[c].Value));
            Console.WriteLine("tolerance golden: largest mean-error difference over " + expected.Count + " prefixes " + InvariantFormat.Number(largest));
        }

        [Test]
        public void LargestDifferencesAreFarBelowTheTolerance()
        {
            // Prints how close the two implementations are (for the record); the assertions are the tolerances above.
            var g = PlacementGolden.Read();
            var result = PlacementError.Evaluate(g.Reference, g.Probes, g.Tetrahedra);
            double worst = 0, worstRelative = 0;
            foreach (var point in g.Json.Get("points").Items)
            {
                int n = (int)point.Get("index").AsNumber;
                foreach (var pair in new[] { Tuple.Create(point.Get("irradiance").AsNumber, result.PointIrradiance[n]), Tuple.Create(point.Get("smape").AsNumber, result.PointSmape[n]) })
                {
                    double d = Math.Abs(pair.Item1 - pair.Item2);
                    worst = Math.Max(worst, d);
                    if (pair.Item1 != 0) worstRelative = Math.Max(worstRelative, d / Math.Abs(pair.Item1));
                }
            }
            double summary = 0;
            foreach (string metric in new[] { "irradiance", "smape" })
            {
                var actual = metric == "irradiance" ? result.Irradiance : result.Smape;
                summary = Math.Max(summary, Math.Abs(g.Json.Get(metric).Get("mean").AsNumber - actual.Mean));
                summary = Math.Max(summary, Math.Abs(g.Json.Get(metric).Get("p95").AsNumber - actual.P95));
            }
            double weight = 0;
            foreach (var point in g.Json.Get("points").Items)
            {
                if (point.Has("probe")) continue;
                var s = PlacementError.StencilOf(g.Reference, g.Probes, g.Tetrahedra, (int)point.Get("index").AsNumber);
                var mine = new Dictionary<int, double>();
                Add(mine, s.Probe0, s.Weight0);
                Add(mine, s.Probe1, s.Weight1);
                Add(mine, s.Probe2, s.Weight2);
                Add(mine, s.Probe3, s.Weight3);
                var theirs = new Dictionary<int, double>();
                int[] vertices = Ints(point.Get("stencil"));
                double[] weights = JsonArrays.Doubles(point.Get("weights"));
                for (int k = 0; k < 4; k++) Add(theirs, vertices[k], weights[k]);
                foreach (int probe in theirs.Keys.Union(mine.Keys))
                {
                    double e, a;
                    theirs.TryGetValue(probe, out e);
                    mine.TryGetValue(probe, out a);
                    weight = Math.Max(weight, Math.Abs(e - a));
                }
            }
            Console.WriteLine("placement golden: largest per-point error difference " + InvariantFormat.Number(worst) + " (relative " +
                              InvariantFormat.Number(worstRelative) + "), summaries " + InvariantFormat.Number(summary) + ", stencil weights " +
                              InvariantFormat.Number(weight));
            Assert.That(worst, Is.LessThan(1e-7));
        }
    }
}
