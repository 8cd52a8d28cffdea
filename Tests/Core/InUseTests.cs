using System;
using System.Collections.Generic;
using System.Numerics;
using System.Threading;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.InUse;
using Lpnn.Probes.Core.Json;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Tests.Support;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    /// <summary>The in-use rule (Documentation~/in-use.md) against Tests/Data/in_use_golden.json, which
    /// Tools~/golden/make_in_use_golden.py builds by construction and Python's test_in_use_golden.py also reads; then its
    /// behaviour on small designed scenes (faces a quarter or an eighth of a cell off the lattice), errors and extremes.</summary>
    [TestFixture]
    public class InUseTests
    {
        private const string Golden = "in_use_golden.json";

        // ------------------------------------------------------------------------------------------------ the golden

        private sealed class GoldenScene
        {
            public JsonValue Json;
            public EvaluationGrid Grid;
            public AnalyticBoxRaycaster Rays;
            public Vector3[] Seeds;
        }

        private static GoldenScene ReadGolden()
        {
            var json = TestData.ReadJson(Golden);
            var ids = new List<LatticeId>();
            foreach (var id in json.Get("ids").Items)
                ids.Add(new LatticeId((int)id.Items[0].AsNumber, (int)id.Items[1].AsNumber, (int)id.Items[2].AsNumber));
            var rays = new AnalyticBoxRaycaster();
            Assert.That(json.Get("room").IsNull, "the golden level has no room box");
            foreach (var box in json.Get("obstacles").Items)
                rays.Boxes.Add(new AxisBox(AnalyticScene.ToDouble3(box.Get("min")), AnalyticScene.ToDouble3(box.Get("max"))));
            var seeds = new List<Vector3>();
            foreach (var seed in json.Get("seeds").Items)
            {
                var p = seed.Get("position").Items;
                seeds.Add(new Vector3((float)p[0].AsNumber, (float)p[1].AsNumber, (float)p[2].AsNumber));
            }
            return new GoldenScene
            {
                Json = json, Grid = EvaluationGrid.FromIds(json.Get("cell_size").AsNumber, ids), Rays = rays, Seeds = seeds.ToArray(),
            };
        }

        private static InUseParameters ParametersOf(JsonValue goldenCase)
        {
            var p = goldenCase.Get("parameters");
            return new InUseParameters(p.Get("band_height").AsNumber, p.Get("slope_limit_degrees").AsNumber, p.Get("step_height").AsNumber);
        }

        private static IEnumerable<int> GoldenCases()
        {
            for (int c = 0; c < 4; c++) yield return c;
        }

        [Test]
        public void TheGoldenHasItsFourCases()
        {
            var scene = ReadGolden();
            Assert.That(scene.Json.Get("cases").Items.Count, Is.EqualTo(4));
            Assert.That(scene.Grid.Count, Is.GreaterThan(1000));
        }

        [TestCaseSource("GoldenCases")]
        public void BandFloorHeightsStartsAndReachableEqualTheGolden(int caseIndex)
        {
            var scene = ReadGolden();
            var c = scene.Json.Get("cases").Items[caseIndex];
            string name = c.Get("name").AsString;
            var parameters = ParametersOf(c);
            double tolerance = scene.Json.Get("tolerance").Get("floor_height").Get("abs").AsNumber;
            var band = InUseMask.Band(scene.Grid, scene.Rays, parameters, null);
            var expectedBand = c.Get("in_band").Items;
            var expectedFloor = c.Get("floor_height").Items;
            for (int p = 0; p < scene.Grid.Count; p++)
            {
                string where = name + ": point " + p + " (id " + scene.Grid.GetId(p) + ")";
                Assert.That(band.InBand[p], Is.EqualTo(expectedBand[p].AsBoolean), where + " in band");
                if (expectedFloor[p].IsNull) Assert.That(double.IsNaN(band.FloorHeights[p]), where + " has no floor");
                else Assert.That(band.FloorHeights[p], Is.EqualTo(expectedFloor[p].AsNumber).Within(tolerance), where + " floor height");
            }

            var starts = SeedAttachment.Starts(scene.Grid, scene.Rays, band.InBand, SeedAttachment.Checked(scene.Seeds), null,
                CancellationToken.None);
            var expectedStarts = new List<int>();
            foreach (var s in c.Get("start_points").Items) expectedStarts.Add((int)s.AsNumber);
            Assert.That(starts, Is.EqualTo(expectedStarts.ToArray()), name + ": start points");

            var reached = InUseMask.Reachable(scene.Grid, scene.Rays, parameters, scene.Seeds, band, null);
            var expectedReached = c.Get("reachable").Items;
            for (int p = 0; p < scene.Grid.Count; p++)
                Assert.That(reached[p], Is.EqualTo(expectedReached[p].AsBoolean), name + ": point " + p + " (id " + scene.Grid.GetId(p) + ") reachable");
            Assert.That(InUseMask.Compute(scene.Grid, scene.Rays, parameters, InUseRule.Reachable, scene.Seeds, null), Is.EqualTo(reached));
            Assert.That(InUseMask.Compute(scene.Grid, scene.Rays, parameters, InUseRule.Band, null, null), Is.EqualTo(band.InBand));
        }

        [Test]
        public void TheLandmarksHold()
        {
            var scene = ReadGolden();
            var masks = new Dictionary<string, bool[][]>();
            foreach (var c in scene.Json.Get("cases").Items)
            {
                var parameters = ParametersOf(c);
                var band = InUseMask.Band(scene.Grid, scene.Rays, parameters, null);
                masks[c.Get("name").AsString] = new[] { band.InBand, InUseMask.Reachable(scene.Grid, scene.Rays, parameters, scene.Seeds, band, null) };
            }
            foreach (var landmark in scene.Json.Get("landmarks").Items)
            {
                var id = landmark.Get("id").Items;
                int point = scene.Grid.IndexOf(new LatticeId((int)id[0].AsNumber, (int)id[1].AsNumber, (int)id[2].AsNumber));
                Assert.That(point, Is.GreaterThanOrEqualTo(0));
                var mask = masks[landmark.Get("case").AsString];
                string why = landmark.Get("case").AsString + ": " + landmark.Get("why").AsString;
                Assert.That(mask[0][point], Is.EqualTo(landmark.Get("in_band").AsBoolean), why + " (in band)");
                Assert.That(mask[1][point], Is.EqualTo(landmark.Get("reachable").AsBoolean), why + " (reachable)");
            }
        }

        // ------------------------------------------------------------------------------------------------ scenes in cells

        private static AxisBox Cells(double h, double[] lo, double[] hi, Double3 origin) =>
            new AxisBox(origin + new Double3(lo[0], lo[1], lo[2]) * h, origin + new Double3(hi[0], hi[1], hi[2]) * h);

        /// <summary>A floor whose top is 0.375 cells below the j = 0 points (x −1..21, z −1..3 cells), and other boxes in cells.</summary>
        private static AnalyticBoxRaycaster FloorAnd(double h, Double3 origin, params double[][] boxes)
        {
            var rays = new AnalyticBoxRaycaster();
            rays.Boxes.Add(Cells(h, new[] { -1.125, -2.0, -1.125 }, new[] { 21.125, -0.375, 3.125 }, origin));
            for (int b = 0; b < boxes.Length; b += 2) rays.Boxes.Add(Cells(h, boxes[b], boxes[b + 1], origin));
            return rays;
        }

        private static AnalyticBoxRaycaster FloorAnd(double h, params double[][] boxes) => FloorAnd(h, Double3.Zero, boxes);

        /// <summary>The lattice points of the id ranges (inclusive) not inside any box, as the validity step would leave them.</summary>
        private static EvaluationGrid GridOutside(AnalyticBoxRaycaster rays, double h, int[] x, int[] y, int[] z, LatticeId offset = default)
        {
            var ids = new List<LatticeId>();
            for (int k = z[0]; k <= z[1]; k++)
            for (int j = y[0]; j <= y[1]; j++)
            for (int i = x[0]; i <= x[1]; i++)
            {
                var id = new LatticeId(i + offset.I, j + offset.J, k + offset.K);
                var p = new Double3(id.I * h, id.J * h, id.K * h);
                bool inside = false;
                for (int b = 1; b < rays.Boxes.Count; b++)
                {
                    var box = rays.Boxes[b];
                    inside |= p.X >= box.Min.X && p.X <= box.Max.X && p.Y >= box.Min.Y && p.Y <= box.Max.Y && p.Z >= box.Min.Z && p.Z <= box.Max.Z;
                }
                if (!inside) ids.Add(id);
            }
            return EvaluationGrid.FromIds(h, ids);
        }

        private static int At(EvaluationGrid grid, int i, int j, int k, LatticeId offset = default)
        {
            int index = grid.IndexOf(new LatticeId(i + offset.I, j + offset.J, k + offset.K));
            Assert.That(index, Is.GreaterThanOrEqualTo(0), "no point " + i + "," + j + "," + k);
            return index;
        }

        /// <summary>Parameters in cells: the band and step scale with h, the slope does not.</summary>
        private static InUseParameters InCells(double h, double band = 2.5, double slope = 45, double step = 0.5) =>
            new InUseParameters(band * h, slope, step * h);

        private static int[] R(int from, int to) => new[] { from, to };
        private static double[] D(params double[] values) => values;

        /// <summary>The plane y = tan(tilt)·x + height (either facing): a box raycaster has only flat floors.</summary>
        private sealed class TiltedPlane : IRaycaster
        {
            private readonly Double3 _normal;
            private readonly double _offset;

            public TiltedPlane(double tiltDegrees, double height)
            {
                double t = tiltDegrees * Math.PI / 180;
                _normal = new Double3(-Math.Sin(t), Math.Cos(t), 0);
                _offset = height * Math.Cos(t);
            }

            public void Cast(Vector3[] origins, Vector3[] directions, float maxDistance, RayHit[] results)
            {
                for (int r = 0; r < origins.Length; r++)
                {
                    double toward = Double3.Dot(Double3.FromVector3(directions[r]), _normal);
                    double side = Double3.Dot(Double3.FromVector3(origins[r]), _normal) - _offset;
                    double t = toward != 0 ? -side / toward : double.PositiveInfinity;
                    results[r] = t >= 0 && t <= maxDistance
                        ? new RayHit { Distance = (float)t, Normal = new Vector3((float)_normal.X, (float)_normal.Y, 0) }
                        : RayHit.Miss;
                }
            }
        }

        private sealed class CountingRaycaster : IRaycaster
        {
            public readonly IRaycaster Inner;
            public long Rays;
            public int Calls;

            public CountingRaycaster(IRaycaster inner) { Inner = inner; }

            public void Cast(Vector3[] origins, Vector3[] directions, float maxDistance, RayHit[] results)
            {
                Rays += origins.Length;
                Calls++;
                Inner.Cast(origins, directions, maxDistance, results);
            }
        }

        // ------------------------------------------------------------------------------------------------ parameters, rules

        [Test]
        public void DefaultsAreTheSpecs()
        {
            var p = new InUseParameters();
            Assert.That(new[] { p.BandHeight, p.SlopeLimitDegrees, p.StepHeight }, Is.EqualTo(new[] { 3.0, 45.0, 0.5 }));
            Assert.That(p.WalkableCosine, Is.EqualTo(Math.Sqrt(0.5)).Within(1e-12));
            Assert.That(p.RiseLimit(0.5), Is.EqualTo(0.75).Within(1e-12));
        }

        [TestCase("band_height", 0.0, "(0, 10000] metres")]
        [TestCase("band_height", 10001.0, "(0, 10000]")]
        [TestCase("band_height", double.NaN, "NaN")]
        [TestCase("slope_limit_degrees", 90.0, "[0, 90) degrees")]
        [TestCase("slope_limit_degrees", -0.5, "[0, 90)")]
        [TestCase("step_height", -0.01, "[0, 10000] metres")]
        [TestCase("step_height", double.PositiveInfinity, "Infinity")]
        public void ParametersOutOfRangeNameTheValueAndTheRange(string field, double value, string fragment)
        {
            var error = Assert.Throws<InUseException>(() => new InUseParameters(
                field == "band_height" ? value : 3.0, field == "slope_limit_degrees" ? value : 45.0, field == "step_height" ? value : 0.5));
            StringAssert.Contains(field, error.Message);
            StringAssert.Contains(fragment, error.Message);
            Assert.That(error, Is.InstanceOf<LpnnException>());
        }

        [Test]
        public void ParametersAtTheEndsOfTheirRangesAreAccepted()
        {
            Assert.DoesNotThrow(() => new InUseParameters(1e4, 0.0, 0.0));
            Assert.DoesNotThrow(() => new InUseParameters(1e-9, 89.999, 1e4));
        }

        [TestCase(1e-4, 1)]
        [TestCase(0.25, 1)]
        [TestCase(0.2501, 2)]
        [TestCase(0.5, 2)]
        [TestCase(16.0, 64)]
        [TestCase(1e4, 64)]
        public void ProfileIntervalsStayInOneTo64(double cellSize, int intervals)
        {
            Assert.That(InUseParameters.ProfileIntervals(cellSize), Is.EqualTo(intervals));
        }

        [Test]
        public void RuleNamesAreThePythonNames()
        {
            foreach (var name in new[] { "reachable", "band", "all" })
                Assert.That(InUseRules.Name(InUseRules.Parse(name)), Is.EqualTo(name));
            Assert.That(InUseRules.Parse("band"), Is.EqualTo(InUseRule.Band));
            StringAssert.Contains("'walk' is not one of reachable, band, all", Assert.Throws<InUseException>(() => InUseRules.Parse("walk")).Message);
        }

        // ------------------------------------------------------------------------------------------------ behaviour

        [Test]
        public void BandIsThePointsWithinHAboveAFloor()
        {
            var rays = FloorAnd(1.0);
            var grid = GridOutside(rays, 1.0, R(0, 2), R(0, 4), R(0, 0));
            var band = InUseMask.Band(grid, rays, InCells(1.0, band: 2.5), null);
            for (int p = 0; p < grid.Count; p++)
            {
                bool expected = grid.GetId(p).J + 0.375 <= 2.5;
                Assert.That(band.InBand[p], Is.EqualTo(expected), "point " + grid.GetId(p));
                if (expected) Assert.That(band.FloorHeights[p], Is.EqualTo(-0.375).Within(1e-6));
                else Assert.That(double.IsNaN(band.FloorHeights[p]));
            }
        }

        [TestCase(40.0, 45.0, true)]
        [TestCase(50.0, 45.0, false)]
        [TestCase(40.0, 35.0, false)]
        [TestCase(0.0, 0.0, true)]
        public void ASteepSurfaceIsNotAFloor(double tilt, double limit, bool walkable)
        {
            var grid = GridOutside(new AnalyticBoxRaycaster(), 1.0, R(-3, 3), R(0, 0), R(0, 0));
            var band = InUseMask.Band(grid, new TiltedPlane(tilt, -4.5), InCells(1.0, band: 10.0, slope: limit), null);
            foreach (bool inBand in band.InBand) Assert.That(inBand, Is.EqualTo(walkable));
        }

        [Test]
        public void AWalkableRampIsClimbedWithinTheSlopePartOfTheAllowance()
        {
            // No step allowance: each profile interval rises (h/M)·tan 40° ≤ (h/M)·tan 45°.
            var grid = GridOutside(new AnalyticBoxRaycaster(), 1.0, R(0, 5), R(0, 7), R(0, 0));
            var seed = new[] { new Vector3(0, 0, 0) };
            var reached = InUseMask.Reachable(grid, new TiltedPlane(40, -0.5), InCells(1.0, band: 2.2, slope: 45, step: 0), seed, null, null);
            Assert.That(reached[At(grid, 5, 4, 0)], "0.3 cells above the ramp, 5 cells along");
            Assert.Throws<InUseException>(() =>
                InUseMask.Reachable(grid, new TiltedPlane(40, -0.5), InCells(1.0, band: 2.2, slope: 39, step: 0), seed, null, null));
        }

        [Test]
        public void AWallTopTwoMetresUpIsInBandButNotReachable()
        {
            double h = 0.5;
            var rays = FloorAnd(h, D(4.25, -0.375, -1.125), D(6.75, 3.875, 3.125)); // 2.125 m above the floor
            var grid = GridOutside(rays, h, R(0, 11), R(0, 6), R(0, 2));
            var parameters = InCells(h, band: 6.0, step: 1.0);
            var band = InUseMask.Band(grid, rays, parameters, null);
            var reached = InUseMask.Reachable(grid, rays, parameters, new[] { new Vector3(0, 0.25f, 0.5f) }, band, null);
            int onTop = At(grid, 5, 4, 1);
            Assert.That(band.InBand[onTop] && !reached[onTop]);
            Assert.That(reached[At(grid, 3, 4, 1)]);
            Assert.That(reached[At(grid, 9, 0, 1)], Is.False, "behind the block");
            var fromTop = InUseMask.Reachable(grid, rays, parameters, new[] { new Vector3(2.75f, 2.125f, 0.5f) }, band, null);
            Assert.That(fromTop[onTop] && fromTop[At(grid, 9, 0, 1)] && fromTop[At(grid, 0, 0, 1)], "a seed on top drops off both sides");
        }

        [Test]
        public void StairsAreClimbedAndAWallOfTheirHeightIsNot()
        {
            double h = 0.5;
            var boxes = new List<double[]>();
            for (int k = 0; k < 7; k++)
            {
                boxes.Add(D(4.25 + 0.5 * k, -0.375, -1.125));
                boxes.Add(D(4.75 + 0.5 * k, -0.375 + 0.3 * (k + 1), 3.125));
            }
            boxes.Add(D(7.75, -0.375, -1.125));
            boxes.Add(D(12.25, -0.375 + 2.4, 3.125));
            var stairs = FloorAnd(h, boxes.ToArray());
            var parameters = InCells(h, band: 5.0);
            var seed = new[] { new Vector3(0.5f, 0.25f, 0) };
            var grid = GridOutside(stairs, h, R(0, 13), R(0, 6), R(0, 1));
            Assert.That(InUseMask.Reachable(grid, stairs, parameters, seed, null, null)[At(grid, 10, 3, 0)], "the landing up the stairs");
            var wall = FloorAnd(h, D(4.25, -0.375, -1.125), D(12.25, 2.025, 3.125));
            grid = GridOutside(wall, h, R(0, 13), R(0, 6), R(0, 1));
            Assert.That(InUseMask.Reachable(grid, wall, parameters, seed, null, null)[At(grid, 10, 3, 0)], Is.False, "a wall as high as the landing");
        }

        [TestCase(true)]
        [TestCase(false)]
        public void AThinWallBetweenRoomsBlocks(bool withWall)
        {
            // Thinner than a profile interval and between its samples: only the segment test sees it.
            var rays = withWall ? FloorAnd(1.0, D(4.6, -0.375, -1.125), D(4.7, 10.0, 3.125)) : FloorAnd(1.0);
            var grid = GridOutside(rays, 1.0, R(0, 9), R(0, 1), R(0, 2));
            var reached = InUseMask.Reachable(grid, rays, InCells(1.0), new[] { new Vector3(1, 0.25f, 1) }, null, null);
            Assert.That(reached[At(grid, 2, 0, 1)]);
            Assert.That(reached[At(grid, 7, 1, 2)], Is.EqualTo(!withWall));
        }

        [TestCase(true)]
        [TestCase(false)]
        public void ASlabBetweenTwoLayersBlocksTheVerticalMove(bool withSlab)
        {
            var rays = withSlab ? FloorAnd(1.0, D(-1.125, 0.375, -1.125), D(2.5, 0.625, 3.125)) : FloorAnd(1.0);
            var grid = GridOutside(new AnalyticBoxRaycaster(), 1.0, R(0, 5), R(0, 2), R(0, 1));
            var reached = InUseMask.Reachable(grid, rays, InCells(1.0), new[] { new Vector3(0, 0.125f, 0) }, null, null);
            Assert.That(reached[At(grid, 0, 0, 0)]);
            Assert.That(reached[At(grid, 0, 1, 0)], Is.EqualTo(!withSlab));
        }

        [Test]
        public void MovesAreDirectedALedgeIsLeftButNotClimbed()
        {
            var rays = FloorAnd(1.0, D(-1.125, -0.375, -1.125), D(3.5, 1.625, 3.125));
            var grid = GridOutside(rays, 1.0, R(0, 7), R(0, 4), R(0, 1));
            var parameters = InCells(1.0, band: 3.0);
            int onLedge = At(grid, 1, 2, 0), below = At(grid, 6, 0, 0);
            var fromLedge = InUseMask.Reachable(grid, rays, parameters, new[] { new Vector3(1, 2, 0) }, null, null);
            Assert.That(fromLedge[onLedge] && fromLedge[below]);
            var fromFloor = InUseMask.Reachable(grid, rays, parameters, new[] { new Vector3(6, 0.25f, 0) }, null, null);
            Assert.That(fromFloor[below] && !fromFloor[onLedge]);
        }

        [Test]
        public void ASeedAttachesWithinTwoCellsAndNotThroughAWall()
        {
            var rays = FloorAnd(1.0, D(4.6, -0.375, -1.125), D(4.7, 10.0, 3.125));
            var grid = GridOutside(rays, 1.0, R(0, 9), R(0, 1), R(0, 0));
            var band = InUseMask.Band(grid, rays, InCells(1.0), null);
            var starts = SeedAttachment.Starts(grid, rays, band.InBand, new[] { new Double3(4.5, 0.25, 0) }, null, CancellationToken.None);
            var xs = new SortedSet<int>();
            foreach (int s in starts) xs.Add(grid.GetId(s).I);
            Assert.That(xs, Is.EqualTo(new[] { 3, 4 }), "|q − s| ≤ 2 reaches x 3..6; 5 and 6 are behind the wall");
            var error = Assert.Throws<InUseException>(() =>
                InUseMask.Reachable(grid, rays, InCells(1.0), new[] { new Vector3(4.5f, 6, 0) }, band, null));
            StringAssert.Contains("none of the 1 seeds attaches", error.Message);
            StringAssert.Contains("'band'", error.Message);
        }

        // ------------------------------------------------------------------------------------------------ rules, errors, progress

        [Test]
        public void AllNeedsNoRaysAndBandOnlyTheFloorRays()
        {
            var counting = new CountingRaycaster(FloorAnd(1.0));
            var grid = GridOutside(new AnalyticBoxRaycaster(), 1.0, R(0, 3), R(0, 3), R(0, 1));
            var all = InUseMask.Compute(grid, counting, InCells(1.0), InUseRule.All, null, null);
            Assert.That(Array.IndexOf(all, false), Is.EqualTo(-1));
            Assert.That(counting.Rays, Is.EqualTo(0));
            var band = InUseMask.Compute(grid, counting, InCells(1.0, band: 1.0), InUseRule.Band, null, null);
            Assert.That(counting.Rays, Is.EqualTo(grid.Count));
            Assert.That(counting.Calls, Is.EqualTo(1));
            for (int p = 0; p < grid.Count; p++) Assert.That(band[p], Is.EqualTo(grid.GetId(p).J == 0));
        }

        [Test]
        public void ErrorsNameTheRuleTheValuesAndTheFix()
        {
            var rays = FloorAnd(0.5);
            var grid = GridOutside(new AnalyticBoxRaycaster(), 0.5, R(0, 3), R(1, 2), R(0, 1));
            var error = Assert.Throws<InUseException>(() => InUseMask.Compute(grid, rays, new InUseParameters(0.05), InUseRule.Band, null, null));
            foreach (var part in new[] { "'band'", "band height 0.05 m", "cell size 0.5 m", "16 points", "'all'" }) StringAssert.Contains(part, error.Message);
            error = Assert.Throws<InUseException>(() =>
                InUseMask.Compute(grid, rays, new InUseParameters(0.05), InUseRule.Reachable, new[] { Vector3.Zero }, null));
            StringAssert.Contains("'reachable' leaves no point", error.Message);
            error = Assert.Throws<InUseException>(() => InUseMask.Compute(grid, rays, new InUseParameters(), InUseRule.Reachable, null, null));
            StringAssert.Contains("needs seeds (none given)", error.Message);
            error = Assert.Throws<InUseException>(() => InUseMask.Compute(grid, rays, new InUseParameters(), InUseRule.Reachable, new Vector3[0], null));
            StringAssert.Contains("at least one seed (0 given)", error.Message);
            error = Assert.Throws<InUseException>(() => InUseMask.Compute(grid, rays, new InUseParameters(), InUseRule.Reachable,
                new[] { Vector3.Zero, new Vector3(float.NaN, 0, 0) }, null));
            StringAssert.Contains("seed 1 is (NaN, 0, 0), not finite", error.Message);
        }

        [Test]
        public void ProgressReportsEveryStageToItsEndAndCancelStops()
        {
            var rays = FloorAnd(1.0);
            var grid = GridOutside(rays, 1.0, R(0, 5), R(0, 2), R(0, 2));
            var last = new Dictionary<string, long[]>();
            InUseMask.Compute(grid, rays, InCells(1.0), InUseRule.Reachable, new[] { new Vector3(2, 0.25f, 1) },
                (stage, done, total) => last[stage] = new[] { done, total });
            Assert.That(last.Keys, Is.EquivalentTo(new[]
            {
                "in use: floor rays", "in use: seed attachment rays", "in use: vertical move rays", "in use: floor profile rays",
                "in use: horizontal move rays",
            }));
            foreach (var report in last.Values)
            {
                Assert.That(report[0], Is.EqualTo(report[1]));
                Assert.That(report[1], Is.GreaterThan(0));
            }
            using (var cancel = new CancellationTokenSource())
            {
                cancel.Cancel();
                Assert.Throws<OperationCanceledException>(() =>
                    InUseMask.Compute(grid, rays, InCells(1.0), InUseRule.Band, null, null, cancel.Token));
            }
        }

        // ------------------------------------------------------------------------------------------------ extremes

        private static readonly double[][] StepAndThinWall =
        {
            D(1.25, -0.375, -1.125), D(2.75, -0.075, 3.125), // a 0.3-cell step
            D(4.6, -0.375, -1.125), D(4.7, 10.0, 3.125), // a thin wall
        };

        [TestCase(1e-4)]
        [TestCase(0.5)]
        [TestCase(1e4)]
        public void TheRuleScalesWithTheCell(double h)
        {
            // One layer 0.375 cells above the floor: the band is at most 1e4 m, one cell at the largest size.
            var rays = FloorAnd(h, StepAndThinWall);
            var grid = GridOutside(rays, h, R(0, 8), R(0, 0), R(0, 1));
            var parameters = InCells(h, band: 1.0);
            var band = InUseMask.Band(grid, rays, parameters, null);
            for (int p = 0; p < grid.Count; p++)
            {
                Assert.That(band.InBand[p]);
                double floor = grid.GetId(p).I == 2 ? -0.075 : -0.375;
                Assert.That(band.FloorHeights[p], Is.EqualTo(floor * h).Within(1e-5 * h));
            }
            var reached = InUseMask.Reachable(grid, rays, parameters, new[] { new Vector3(0, (float)(0.125 * h), (float)(0.5 * h)) }, band, null);
            for (int p = 0; p < grid.Count; p++) Assert.That(reached[p], Is.EqualTo(grid.GetId(p).I <= 4), "point " + grid.GetId(p));
        }

        [Test]
        public void FarFromTheOriginGivesTheSameMasks()
        {
            double h = 0.5;
            var shift = new LatticeId(200000, 2, -200000); // 1e5 m, 1 m, −1e5 m
            var origin = new Double3(shift.I * h, shift.J * h, shift.K * h);
            var near = FloorAnd(h, StepAndThinWall);
            var far = FloorAnd(h, origin, StepAndThinWall);
            var nearGrid = GridOutside(near, h, R(0, 8), R(0, 1), R(0, 1));
            var farGrid = GridOutside(far, h, R(0, 8), R(0, 1), R(0, 1), shift);
            var parameters = InCells(h, band: 2.0);
            var seed = new Vector3(0, 0.0625f, 0.25f);
            var nearMask = InUseMask.Reachable(nearGrid, near, parameters, new[] { seed }, null, null);
            var farMask = InUseMask.Reachable(farGrid, far, parameters,
                new[] { seed + new Vector3((float)origin.X, (float)origin.Y, (float)origin.Z) }, null, null);
            Assert.That(farMask, Is.EqualTo(nearMask));
            Assert.That(Array.IndexOf(nearMask, true), Is.GreaterThanOrEqualTo(0));
            Assert.That(Array.IndexOf(nearMask, false), Is.GreaterThanOrEqualTo(0));
        }

        [Test]
        public void OnePoint()
        {
            var rays = FloorAnd(0.5);
            var grid = EvaluationGrid.FromIds(0.5, new[] { new LatticeId(0, 0, 0) });
            Assert.That(InUseMask.Compute(grid, rays, new InUseParameters(), InUseRule.Band, null, null), Is.EqualTo(new[] { true }));
            Assert.That(InUseMask.Compute(grid, rays, new InUseParameters(), InUseRule.Reachable, new[] { new Vector3(0, 0.1f, 0) }, null),
                Is.EqualTo(new[] { true }));
            Assert.Throws<InUseException>(() =>
                InUseMask.Compute(grid, rays, new InUseParameters(), InUseRule.Reachable, new[] { new Vector3(5, 0, 0) }, null));
        }

        [Test]
        public void SeedsBeyondTheLatticeAttachToNothing()
        {
            double h = 1e-4;
            var rays = FloorAnd(h);
            var grid = GridOutside(rays, h, R(0, 2), R(0, 0), R(0, 0));
            var error = Assert.Throws<InUseException>(() => InUseMask.Reachable(grid, rays, InCells(h), new[]
            {
                new Vector3(1e30f, 0, 0), new Vector3(-3e38f, 0, 0),
            }, null, null));
            StringAssert.Contains("none of the 2 seeds", error.Message);
        }

        [Test]
        public void TheWalkReachesWhatAPlainSearchReaches()
        {
            var random = new Random(7);
            for (int trial = 0; trial < 5; trial++)
            {
                int n = 300;
                var sources = new List<int>();
                var targets = new List<int>();
                for (int m = 0; m < 400; m++)
                {
                    sources.Add(random.Next(n));
                    targets.Add(random.Next(n));
                }
                var starts = new[] { random.Next(n), random.Next(n) };
                Array.Sort(starts);
                var expected = new bool[n];
                var stack = new Stack<int>(starts);
                foreach (int s in starts) expected[s] = true;
                while (stack.Count > 0)
                {
                    int p = stack.Pop();
                    for (int m = 0; m < sources.Count; m++)
                    {
                        if (sources[m] != p || expected[targets[m]]) continue;
                        expected[targets[m]] = true;
                        stack.Push(targets[m]);
                    }
                }
                Assert.That(ReachableWalk.Reach(n, starts, sources, targets), Is.EqualTo(expected));
            }
        }
    }
}
