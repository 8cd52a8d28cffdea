using System;
using System.Collections.Generic;
using System.Numerics;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Selection;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    /// <summary>Invalid points (inside geometry) never become probes, whatever the policy or completion step.</summary>
    [TestFixture]
    public class ValidCandidatesTests
    {
        private const int Size = 6;

        private static EvaluationGrid Cube() =>
            GridBuilder.Build(new[] { GridBox.AxisAligned(Double3.Zero, new Double3(Size - 1, Size - 1, Size - 1)) }, 1);

        /// <summary>The slab x ≤ 1 (which holds four of the box's corners) is inside geometry.</summary>
        private static bool[] SlabInvalid(EvaluationGrid grid)
        {
            var valid = new bool[grid.Count];
            for (int n = 0; n < grid.Count; n++) valid[n] = grid.GetId(n).I > 1;
            return valid;
        }

        /// <summary>Scores highest inside the slab, so any path that ignores validity picks invalid points first.</summary>
        private static float[] ScoresFavouringTheSlab(EvaluationGrid grid)
        {
            var scores = new float[grid.Count];
            for (int n = 0; n < grid.Count; n++)
            {
                var id = grid.GetId(n);
                scores[n] = (id.I <= 1 ? 10f : 0f) + 0.01f * ((n * 7) % 13);
            }
            return scores;
        }

        private static void AssertAllValid(SelectionResult result, bool[] valid, string policy)
        {
            Assert.That(result.Indices.Length, Is.GreaterThanOrEqualTo(4), policy);
            foreach (int index in result.Indices) Assert.That(valid[index], Is.True, policy + ": point " + index + " is invalid");
        }

        /// <summary>Every mean error it was asked for, recording the probe sets.</summary>
        private sealed class CountingMeasure : IPlacementErrorMeasure
        {
            public readonly List<int[]> Asked = new List<int[]>();

            public double MeanError(int[] probeIndices)
            {
                Asked.Add(probeIndices);
                return 1.0 / probeIndices.Length;
            }
        }

        [Test]
        public void ARankingNotMadeOfScoresNeverYieldsAnInvalidPoint()
        {
            // The insertion method's path (ProbeSelector.SelectFromRanking): a ranking that lists the slab's points first.
            var grid = Cube();
            var valid = SlabInvalid(grid);
            var ranking = ScoreRanking.Rank(ScoresFavouringTheSlab(grid));
            var settings = new[]
            {
                SelectionSettings.Percentile(0.9, true), SelectionSettings.Budget(20, true), SelectionSettings.Budget(1, true),
                SelectionSettings.Spread(12, true), SelectionSettings.Budget(1),
            };
            foreach (var setting in settings)
            {
                AssertAllValid(ProbeSelector.SelectFromRanking(grid, ranking, setting, null, valid), valid, setting.Policy + " " + setting.Value);
                // Control: without the flags the same ranking does pick slab points.
                var unmasked = ProbeSelector.SelectFromRanking(grid, ranking, setting, null);
                Assert.That(Array.Exists(unmasked.Indices, index => !valid[index]), Is.True, "control " + setting.Policy);
            }
            var measure = new CountingMeasure();
            AssertAllValid(ProbeSelector.SelectFromRanking(grid, ranking, SelectionSettings.Tolerance(0.02, true), measure, valid), valid, "tolerance");
            foreach (var asked in measure.Asked)
                foreach (int index in asked) Assert.That(valid[index], Is.True, "a measured set holds invalid point " + index);
            // Fewer than 4 valid points is refused with the counts, not answered with invalid ones.
            var almostNone = new bool[grid.Count];
            almostNone[0] = almostNone[1] = true;
            Assert.Throws<SelectionException>(() => ProbeSelector.SelectFromRanking(grid, ranking, SelectionSettings.Budget(20), null, almostNone));
        }

        [Test]
        public void NoPolicyNorCompletionStepSelectsAnInvalidPoint()
        {
            var grid = Cube();
            var valid = SlabInvalid(grid);
            var scores = ScoresFavouringTheSlab(grid);
            var points = new ScoredPoints(grid, scores, valid);
            Assert.That(points.ValidCount, Is.EqualTo(4 * Size * Size));
            var settings = new[]
            {
                SelectionSettings.Percentile(0.9, true), SelectionSettings.Budget(20, true), SelectionSettings.Budget(1, true),
                SelectionSettings.Spread(12, true), SelectionSettings.Spread(1000, true), SelectionSettings.Threshold(0.5, true),
                SelectionSettings.Threshold(1.0, true), SelectionSettings.Budget(1),
            };
            foreach (var setting in settings)
                AssertAllValid(ProbeSelector.Select(points, setting, null), valid, setting.Policy + " " + setting.Value);

            var measure = new CountingMeasure();
            var tolerance = ProbeSelector.Select(points, SelectionSettings.Tolerance(0.02, true), measure);
            AssertAllValid(tolerance, valid, "tolerance");
            Assert.That(measure.Asked, Is.Not.Empty);
            foreach (var asked in measure.Asked)
                foreach (int index in asked) Assert.That(valid[index], Is.True, "the tolerance search measured a set with invalid point " + index);
        }

        [Test]
        public void WithoutTheMaskTheSameScoresWouldPickTheSlab()
        {
            // the control: the fixture above is meaningful only if ignoring validity does pick invalid points
            var grid = Cube();
            var valid = SlabInvalid(grid);
            var unmasked = ProbeSelector.Select(new ScoredPoints(grid, ScoresFavouringTheSlab(grid)), SelectionSettings.Budget(20, true), null);
            Assert.That(Array.Exists(unmasked.Indices, index => !valid[index]), Is.True);
        }

        [Test]
        public void TheSpreadOrderRanksTheValidPointsOnly()
        {
            var grid = Cube();
            var valid = SlabInvalid(grid);
            var points = new ScoredPoints(grid, ScoresFavouringTheSlab(grid), valid);
            Assert.That(points.SpreadOrder.Length, Is.EqualTo(points.ValidCount));
            Assert.That(points.ScoreOrder.Length, Is.EqualTo(points.ValidCount));
            Assert.That(new HashSet<int>(points.SpreadOrder).Count, Is.EqualTo(points.ValidCount));
            foreach (int index in points.SpreadOrder) Assert.That(valid[index], Is.True);
        }

        [Test]
        public void TooFewOrFlatValidPointsAreRefusedSayingWhatToDo()
        {
            var grid = Cube();
            var three = new bool[grid.Count];
            three[0] = three[1] = three[Size] = true;
            var error = Assert.Throws<SelectionException>(() => new ScoredPoints(grid, new float[grid.Count], three));
            StringAssert.Contains("only 3 of 216 evaluation points are valid", error.Message);
            StringAssert.Contains("inside geometry", error.Message);
            StringAssert.Contains("move or enlarge the volume's boxes", error.Message);

            var plane = new bool[grid.Count];
            for (int n = 0; n < grid.Count; n++) plane[n] = grid.GetId(n).K == 2;
            StringAssert.Contains("all in one plane", Assert.Throws<SelectionException>(() => ValidCandidates.Check(grid, plane)).Message);
            var line = new bool[grid.Count];
            for (int n = 0; n < grid.Count; n++) line[n] = grid.GetId(n).J == 0 && grid.GetId(n).K == 0;
            StringAssert.Contains("all on one line", Assert.Throws<SelectionException>(() => ValidCandidates.Check(grid, line)).Message);
            StringAssert.Contains("none at all", Assert.Throws<SelectionException>(() => ValidCandidates.Check(grid, new bool[grid.Count])).Message);

            var tetrahedron = new bool[grid.Count];
            tetrahedron[0] = tetrahedron[1] = tetrahedron[Size] = tetrahedron[Size * Size] = true;
            Assert.That(ValidCandidates.Check(grid, tetrahedron), Is.EqualTo(4));
        }

        [Test]
        public void AToleranceRankingThatNamesAnInvalidPointIsRefused()
        {
            var grid = Cube();
            var valid = SlabInvalid(grid);
            var ranking = new ScoredPoints(grid, new float[grid.Count], valid).SpreadOrder;
            ranking = (int[])ranking.Clone();
            ranking[3] = 0; // point 0 (id 0,0,0) is in the slab
            var error = Assert.Throws<SelectionException>(() =>
                ProbeSelector.WithinTolerance(grid, ranking, SelectionSettings.Tolerance(0.5), new CountingMeasure(), valid));
            StringAssert.Contains("inside geometry", error.Message);
        }

        [Test]
        public void TheNetworkSeesOnlyTheValidRowsAndInvalidPointsScoreZero()
        {
            var schema = FeatureSchema.LpnnV1;
            int stride = schema.Count;
            var values = new float[4 * stride];
            for (int i = 0; i < values.Length; i++) values[i] = i;
            var features = new FeatureSet(schema, 4, values, 2.0, new[] { 0f, 0.9f, 0.1f, 1f });
            var valid = new[] { true, false, true, false };
            var rows = ValidCandidates.ValidRows(features, valid);
            Assert.That(rows.PointCount, Is.EqualTo(2));
            Assert.That(rows[0, 0], Is.EqualTo(0f));
            Assert.That(rows[1, 0], Is.EqualTo(2f * stride), "the second valid row is grid point 2");
            Assert.That(rows[1, stride - 1], Is.EqualTo(3f * stride - 1));
            Assert.That(rows.BackFaceFractions, Is.EqualTo(new[] { 0f, 0.1f }));
            Assert.That(rows.LightingScale, Is.EqualTo(2.0));
            Assert.That(ValidCandidates.Scatter(new[] { 0.7f, 0.3f }, valid), Is.EqualTo(new[] { 0.7f, 0f, 0.3f, 0f }));
            Assert.Throws<SelectionException>(() => ValidCandidates.Scatter(new[] { 0.7f }, valid));
            Assert.That(ValidCandidates.ValidRows(features, null), Is.SameAs(features));
        }

        [Test]
        public void FractionsBecomeTheMaskAtTheThresholdAndBadFractionsAreRefused()
        {
            Assert.That(ValidCandidates.FromBackFaceFractions(new[] { 0f, 0.25f, 6f / 26, 7f / 26, 1f }),
                Is.EqualTo(new[] { true, true, true, false, false }));
            StringAssert.Contains("point 1", Assert.Throws<SelectionException>(() => ValidCandidates.FromBackFaceFractions(new[] { 0f, float.NaN })).Message);
            Assert.Throws<SelectionException>(() => ValidCandidates.FromBackFaceFractions(new[] { 1.5f }));
        }

        /// <summary>A solid block x ∈ [1.5, 3.5] seen from inside (every face's normal points out of the block) and from
        /// outside; rays pass nothing else.</summary>
        private sealed class SolidSlabRaycaster : IRaycaster
        {
            public void Cast(Vector3[] origins, Vector3[] directions, float maxDistance, RayHit[] results)
            {
                for (int r = 0; r < origins.Length; r++)
                {
                    results[r] = RayHit.Miss;
                    float x = origins[r].X, dx = directions[r].X;
                    if (dx == 0) continue;
                    foreach (float face in new[] { 1.5f, 3.5f })
                    {
                        float t = (face - x) / dx;
                        if (t < 0 || t > maxDistance || t >= results[r].Distance) continue;
                        results[r] = new RayHit { Distance = t, Normal = new Vector3(face < 2 ? -1 : 1, 0, 0) };
                    }
                }
            }
        }

        [Test]
        public void TheFeatureRaysGiveEachPointsBackFaceFraction()
        {
            var grid = GridBuilder.Build(new[] { GridBox.AxisAligned(Double3.Zero, new Double3(5, 2, 2)) }, 1);
            var sh = new float[grid.Count * 27];
            for (int n = 0; n < grid.Count; n++) sh[27 * n] = 1f;
            var features = FeatureExtractor.Extract(grid, sh, new SolidSlabRaycaster());
            var valid = ValidCandidates.FromBackFaceFractions(features.BackFaceFractions);
            for (int n = 0; n < grid.Count; n++)
            {
                int i = grid.GetId(n).I;
                bool inside = i == 2 || i == 3;
                // inside: every ray with an x component (18 of 26) meets a face from behind; outside: only front faces
                Assert.That(features.BackFaceFractions[n], Is.EqualTo(inside ? 18f / 26 : 0f).Within(1e-6), "point " + n);
                Assert.That(valid[n], Is.EqualTo(!inside), "point " + n);
            }
            // an exported capture carries the fractions, so `lpnn place` can exclude the same points
            var capture = Lpnn.Probes.Core.Captures.Capture.FromGrid(grid, sh, features);
            var section = capture.ExtraSections[0];
            Assert.That(section.Name, Is.EqualTo(ProbeValidity.CaptureSection));
            Assert.That(section.DType, Is.EqualTo("float32"));
            Assert.That(section.Shape, Is.EqualTo(new[] { grid.Count }));
            Assert.That(BitConverter.ToSingle(section.Data, 4 * 2), Is.EqualTo(features.BackFaceFractions[2]));
        }
    }
}
