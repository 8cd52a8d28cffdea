using System;
using System.Collections.Generic;
using System.Numerics;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Labels;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Selection;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    [TestFixture]
    public class SelectionTests
    {
        private static EvaluationGrid Cube(int size, double cell = 1) =>
            GridBuilder.Build(new[] { GridBox.AxisAligned(Double3.Zero, new Double3(size - 1, size - 1, size - 1) * cell) }, cell);

        private static bool Coplanar(EvaluationGrid grid, int[] indices)
        {
            var p0 = grid.GetPosition(indices[0]);
            for (int a = 1; a < indices.Length; a++)
            for (int b = a + 1; b < indices.Length; b++)
            {
                var normal = Vector3.Cross(grid.GetPosition(indices[a]) - p0, grid.GetPosition(indices[b]) - p0);
                if (normal.LengthSquared() == 0) continue;
                foreach (int c in indices)
                    if (Math.Abs(Vector3.Dot(normal, grid.GetPosition(c) - p0)) > 1e-3) return false;
                return true;
            }
            return true;
        }

        [Test]
        public void RankingPutsInfinityFirstNanLastAndBreaksTiesByIndex()
        {
            float[] scores = { 0.5f, float.NaN, float.PositiveInfinity, 0.5f, float.NegativeInfinity, 0.9f };
            Assert.That(ScoreRanking.Rank(scores), Is.EqualTo(new[] { 2, 5, 0, 3, 4, 1 }));
        }

        [Test]
        public void RemapSurvivesEqualInfiniteNanAndHugeScores()
        {
            Assert.That(ScoreRanking.Remap(new[] { 0.3f, 0.3f, 0.3f }), Is.EqualTo(new[] { 1.0, 1.0, 1.0 }));
            Assert.That(ScoreRanking.Remap(new[] { 1f, 3f, 2f }), Is.EqualTo(new[] { 0.0, 1.0, 0.5 }));
            Assert.That(ScoreRanking.Remap(new[] { float.NaN, float.PositiveInfinity, float.NegativeInfinity, 2f }), Is.EqualTo(new[] { 0.0, 1.0, 0.0, 1.0 }));
            var huge = ScoreRanking.Remap(new[] { -3e38f, 3e38f, 0f });
            Assert.That(huge[0], Is.EqualTo(0.0));
            Assert.That(huge[1], Is.EqualTo(1.0));
            Assert.That(huge[2], Is.EqualTo(0.5).Within(1e-9));
            Assert.That(ScoreRanking.Remap(new float[0]), Is.Empty);
        }

        [TestCase(0.9, 100, 10)]
        [TestCase(0.95, 10, 1)]
        [TestCase(0.96, 10, 0)]
        [TestCase(0.0, 7, 7)]
        [TestCase(1.0, 7, 0)]
        [TestCase(0.7, 3, 1)]
        [TestCase(0.9, 125, 13)]
        public void PercentileMeansKeepTheTopShareRoundedHalvesUp(double percentile, int points, int expected)
        {
            Assert.That(ProbeSelector.PercentileCount(percentile, points), Is.EqualTo(expected));
        }

        [Test]
        public void PoliciesKeepTheHighestRankedPoints()
        {
            var grid = Cube(5);
            var scores = new float[grid.Count];
            var random = new Random(3);
            for (int n = 0; n < scores.Length; n++) scores[n] = (float)random.NextDouble();
            var ranking = ScoreRanking.Rank(scores);
            var top = ProbeSelector.Select(grid, scores, SelectionSettings.Percentile(0.9));
            Assert.That(top.Indices.Length, Is.EqualTo(13), "floor(0.1·125 + 0.5)");
            var expected = new List<int>(ranking).GetRange(0, 13);
            expected.Sort();
            Assert.That(top.Indices, Is.EqualTo(expected.ToArray()));
            Assert.That(ProbeSelector.Select(grid, scores, SelectionSettings.Budget(20)).Indices.Length, Is.EqualTo(20));
            Assert.That(ProbeSelector.Select(grid, scores, SelectionSettings.Budget(1000)).Indices.Length, Is.EqualTo(grid.Count));
            var thresholded = ProbeSelector.Select(grid, scores, SelectionSettings.Threshold(0.8));
            double[] remapped = ScoreRanking.Remap(scores);
            foreach (int index in thresholded.Indices) Assert.That(remapped[index], Is.GreaterThanOrEqualTo(0.8));
        }

        [Test]
        public void AllEqualScoresGiveADeterministicSetWithoutDuplicates()
        {
            var grid = Cube(4);
            var scores = new float[grid.Count];
            var a = ProbeSelector.Select(grid, scores, SelectionSettings.Budget(10));
            var b = ProbeSelector.Select(grid, scores, SelectionSettings.Budget(10));
            Assert.That(a.Indices, Is.EqualTo(b.Indices));
            Assert.That(new HashSet<int>(a.Indices).Count, Is.EqualTo(a.Indices.Length));
            Assert.That(ProbeSelector.Select(grid, scores, SelectionSettings.Threshold(1.0)).Indices.Length, Is.EqualTo(grid.Count),
                "equal scores remap to 1: none is less important than another");
        }

        [Test]
        public void FewerThanFourProbesAreCompletedToATetrahedron()
        {
            var grid = Cube(3);
            var scores = new float[grid.Count];
            for (int n = 0; n < scores.Length; n++) scores[n] = n;
            var result = ProbeSelector.Select(grid, scores, SelectionSettings.Budget(1));
            Assert.That(result.Indices.Length, Is.EqualTo(4));
            Assert.That(result.AddedForTetrahedron, Is.EqualTo(3));
            Assert.That(Coplanar(grid, result.Indices), Is.False);
        }

        [Test]
        public void CoplanarTopPointsGetTheHighestRankedPointOffThePlane()
        {
            var grid = Cube(4);
            var scores = new float[grid.Count];
            int best = -1;
            for (int n = 0; n < grid.Count; n++)
            {
                var id = grid.GetId(n);
                scores[n] = id.K == 0 ? 10 + n : (id.K == 2 ? 5 : 1);
                if (id.K == 2 && best < 0) best = n; // first z=2 point: highest-ranked off the plane (ties by index)
            }
            var result = ProbeSelector.Select(grid, scores, SelectionSettings.Budget(16));
            Assert.That(result.AddedForTetrahedron, Is.EqualTo(1));
            Assert.That(result.Indices, Has.Member(best));
            Assert.That(result.Indices.Length, Is.EqualTo(17));
        }

        [Test]
        public void FlatLinearAndSinglePointGridsExplainWhatToChange()
        {
            var flat = GridBuilder.Build(new[] { GridBox.AxisAligned(new Double3(0, 0, 0.2), new Double3(3, 3, 0.2)) }, 1);
            var error = Assert.Throws<SelectionException>(() => ProbeSelector.Select(flat, new float[flat.Count], SelectionSettings.Budget(4)));
            StringAssert.Contains("one cell thick along z", error.Message);
            StringAssert.Contains("at least two cells deep", error.Message);
            var line = GridBuilder.Build(new[] { GridBox.AxisAligned(new Double3(0, 0.2, 0.2), new Double3(5, 0.2, 0.2)) }, 1);
            StringAssert.Contains("one line", Assert.Throws<SelectionException>(() => ProbeSelector.Select(line, new float[line.Count], SelectionSettings.Budget(4))).Message);
            var point = GridBuilder.Build(new[] { GridBox.AxisAligned(new Double3(0.2, 0.2, 0.2), new Double3(0.2, 0.2, 0.2)) }, 1);
            StringAssert.Contains("a single point", Assert.Throws<SelectionException>(() => ProbeSelector.Select(point, new float[1], SelectionSettings.Budget(4))).Message);
        }

        [Test]
        public void CoplanarityIsExactFarFromTheOrigin()
        {
            // Ids near 2^30: float positions cannot tell these points apart, integer ids can.
            const int big = (1 << 30) - 10;
            var ids = new[]
            {
                new LatticeId(big, big, big), new LatticeId(big + 1, big, big), new LatticeId(big, big + 1, big),
                new LatticeId(big + 1, big + 1, big), new LatticeId(big, big, big + 1),
            };
            Array.Sort(ids);
            var grid = EvaluationGrid.FromIds(1e-3, ids);
            var scores = new float[grid.Count];
            for (int n = 0; n < grid.Count; n++) scores[n] = grid.GetId(n).K == big ? 1 : 0;
            var result = ProbeSelector.Select(grid, scores, SelectionSettings.Budget(4));
            Assert.That(result.AddedForTetrahedron, Is.EqualTo(1));
            Assert.That(result.Indices.Length, Is.EqualTo(5));
        }

        [Test]
        public void KeepBoundsCornersAddsTheEightCornerPointsOfEachBox()
        {
            var box = GridBox.AxisAligned(new Double3(0.2, 0.2, 0.2), new Double3(3.7, 2.2, 1.8));
            var grid = GridBuilder.Build(new[] { box }, 1);
            var scores = new float[grid.Count];
            scores[grid.IndexOf(new LatticeId(2, 1, 1))] = 1;
            var result = ProbeSelector.Select(grid, scores, SelectionSettings.Budget(1, keepCorners: true));
            Assert.That(result.CornersAdded, Is.EqualTo(8));
            foreach (var corner in new[] { new LatticeId(0, 0, 0), new LatticeId(4, 2, 2), new LatticeId(4, 0, 2), new LatticeId(0, 2, 0) })
                Assert.That(result.Indices, Has.Member(grid.IndexOf(corner)));
            Assert.That(result.AddedForTetrahedron, Is.EqualTo(0));
            var rebuilt = EvaluationGrid.FromIds(1, new[] { new LatticeId(0, 0, 0) });
            Assert.Throws<SelectionException>(() => ProbeSelector.Select(rebuilt, new float[1], SelectionSettings.Budget(1, true)));
        }

        [TestCase(SelectionPolicy.Percentile, 1.5, "percentile 1.5")]
        [TestCase(SelectionPolicy.Percentile, double.NaN, "percentile NaN")]
        [TestCase(SelectionPolicy.Budget, 0.0, "probe budget 0")]
        [TestCase(SelectionPolicy.Budget, 2.5, "probe budget 2.5")]
        [TestCase(SelectionPolicy.Threshold, -0.1, "score threshold -0.1")]
        public void OutOfRangeParametersAreRejectedNamingTheValue(SelectionPolicy policy, double value, string expected)
        {
            var grid = Cube(3);
            var settings = new SelectionSettings { Policy = policy, Value = value };
            StringAssert.Contains(expected, Assert.Throws<SelectionException>(() => ProbeSelector.Select(grid, new float[grid.Count], settings)).Message);
            StringAssert.Contains("one score per evaluation point",
                Assert.Throws<SelectionException>(() => ProbeSelector.Select(grid, new float[3], SelectionSettings.Budget(4))).Message);
        }

        [Test]
        public void LabelsMarkCellsHoldingAGroundTruthProbeWithHalfOpenCells()
        {
            var grid = Cube(3);
            var probes = new[]
            {
                new Vector3(0.49f, 0.1f, -0.2f), // cell of (0,0,0)
                new Vector3(0.5f, 0f, 0f), // exactly on the boundary: belongs to (1,0,0)
                new Vector3(1.2f, 0.9f, 1.1f), // (1,1,1)
                new Vector3(1.1f, 1.05f, 0.95f), // (1,1,1) again
                new Vector3(9f, 9f, 9f), // outside
                new Vector3(1e12f, 0, 0), // far outside, no overflow
            };
            var result = ProbeLabeler.Label(grid, probes);
            Assert.That(result.Labels[grid.IndexOf(new LatticeId(0, 0, 0))], Is.EqualTo(1));
            Assert.That(result.Labels[grid.IndexOf(new LatticeId(1, 0, 0))], Is.EqualTo(1));
            Assert.That(result.Labels[grid.IndexOf(new LatticeId(1, 1, 1))], Is.EqualTo(1));
            Assert.That(result.PositivePoints, Is.EqualTo(3));
            Assert.That(result.ProbesMatched, Is.EqualTo(4));
            Assert.That(result.ProbesOutside, Is.EqualTo(2));
            int sum = 0;
            foreach (byte label in result.Labels) sum += label;
            Assert.That(sum, Is.EqualTo(3));
            var error = Assert.Throws<LpnnException>(() => ProbeLabeler.Label(grid, new[] { Vector3.Zero, new Vector3(float.NaN, 0, 0) }));
            StringAssert.Contains("ground-truth probe 1", error.Message);
        }
    }
}
