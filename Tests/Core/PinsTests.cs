using System;
using System.Collections.Generic;
using System.Linq;
using System.Numerics;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Json;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Pipeline;
using Lpnn.Probes.Core.Quality;
using Lpnn.Probes.Core.Selection;
using Lpnn.Probes.Core.Tests.Support;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    /// <summary>Pinned probes (Documentation~/pins.md): snapping and blocking against Tests/Data/pins_golden.json (built by
    /// construction, the cases Python's test_quality_pins_golden.py reads), and the insertion order and the refinement
    /// keeping the pins.</summary>
    [TestFixture]
    public class PinsTests
    {
        [Test]
        public void TheConstantsAreTheGoldenFiles()
        {
            var golden = TestData.ReadJson("pins_golden.json");
            Assert.That(golden.Get("snap_radius_cells").AsNumber, Is.EqualTo(Pins.SnapRadiusCells));
            Assert.That(golden.Get("min_distance_cells").AsNumber, Is.EqualTo(Pins.MinDistanceCells));
            Assert.That(golden.Get("slack_cells").AsNumber, Is.EqualTo(Pins.SlackCells));
        }

        [Test]
        public void EveryGoldenCaseSnapsAndBlocksAsBuilt()
        {
            var cases = TestData.ReadJson("pins_golden.json").Get("cases").Items;
            int failing = 0;
            foreach (var c in cases)
            {
                string name = c.Get("name").AsString;
                var ids = c.Get("ids").Items.Select(v => new LatticeId((int)v.Items[0].AsNumber, (int)v.Items[1].AsNumber, (int)v.Items[2].AsNumber)).ToList();
                var grid = EvaluationGrid.FromIds(c.Get("cell_size").AsNumber, ids);
                var pins = c.Get("pins").Items.Select(AnalyticScene.ToDouble3).ToArray();
                var minimum = c.Get("min_distance");
                double? minDistance = minimum.Kind == JsonKind.Null ? (double?)null : minimum.AsNumber;
                if (c.Has("error"))
                {
                    failing++;
                    var error = Assert.Throws<PinException>(() => Pins.Snap(grid, pins, minDistance), name);
                    StringAssert.Contains(c.Get("error").AsString, error.Message, name);
                    continue;
                }
                var snapped = Pins.Snap(grid, pins, minDistance);
                Assert.That(snapped.Indices, Is.EqualTo(c.Get("indices").Items.Select(v => (int)v.AsNumber).ToArray()), name);
                var blocked = Enumerable.Range(0, grid.Count).Where(n => snapped.Blocked[n]).ToArray();
                Assert.That(blocked, Is.EqualTo(c.Get("blocked").Items.Select(v => (int)v.AsNumber).ToArray()), name);
            }
            Assert.That(failing, Is.GreaterThan(0).And.LessThan(cases.Count));
        }

        [Test]
        public void ANonFinitePinAndASmallBudgetAreRefusedByName()
        {
            var grid = QualityFixtures.Box(4, 3, 3);
            var nan = Assert.Throws<PinException>(() => Pins.Snap(grid, new[] { new Double3(0, double.NaN, 0) }));
            StringAssert.Contains("pinned probe 0 is at (0, NaN, 0), not a finite position", nan.Message);
            var pins = Pins.Snap(grid, new[] { new Double3(0, 0, 0), new Double3(3, 2, 2), new Double3(1, 1, 1) });
            var small = Assert.Throws<PinException>(() => pins.CheckCount(2));
            StringAssert.Contains("the budget keeps 2 probes but 3 are pinned", small.Message);
        }

        private static Double3[] OffGridPins(EvaluationGrid grid, int every)
        {
            var pins = new List<Double3>();
            for (int n = 0; n < grid.Count; n += every)
            {
                var v = grid.GetPosition(n);
                pins.Add(new Double3(v.X + 0.3 * grid.CellSize, v.Y, v.Z));
            }
            return pins.ToArray();
        }

        [Test]
        public void InsertionRanksThePinsFirstAndNeverAPointNearOne()
        {
            var grid = QualityFixtures.Box(6, 5, 4);
            var positions = QualityFixtures.Positions(grid);
            var sh = QualityFixtures.BlobField(positions, new Vector3(2, 1, 1), new Vector3(4, 3, 2), 1.3f);
            var pins = Pins.Snap(grid, OffGridPins(grid, 11));
            var order = InsertionOrder.OfValid(grid, sh, ReferenceLighting.FromGrid(grid, sh).SceneScale, null, new BowyerWatsonDelaunay(), pins);
            int[] ranking = order.All();
            Assert.That(ranking.Take(pins.Count), Is.EqualTo(pins.Indices));
            Assert.That(ranking.Distinct().Count(), Is.EqualTo(ranking.Length));
            Assert.That(ranking.Skip(pins.Count).Where(p => pins.Blocked[p]), Is.Empty);
            var expected = Enumerable.Range(0, grid.Count).Where(p => !pins.Blocked[p] || pins.Indices.Contains(p));
            Assert.That(ranking.OrderBy(p => p), Is.EqualTo(expected));
            Assert.That(expected.Count(), Is.LessThan(grid.Count), "some points are blocked here");
            // Without pins: the plain order, unchanged.
            Assert.That(InsertionOrder.OfValid(grid, sh, ReferenceLighting.FromGrid(grid, sh).SceneScale, null, new BowyerWatsonDelaunay()).All(),
                Is.EqualTo(InsertionRanking.Rank(grid, ReferenceLighting.FromGrid(grid, sh), new BowyerWatsonDelaunay())));
        }

        [TestCase(SelectionPolicy.Budget, 36)]
        [TestCase(SelectionPolicy.Tolerance, 0.05)]
        public void TheRefinedSelectionKeepsEveryPinAndNoNewProbeNearOne(SelectionPolicy policy, double value)
        {
            var grid = QualityFixtures.Box(6, 5, 4);
            var positions = QualityFixtures.Positions(grid);
            var sh = QualityFixtures.BlobField(positions, new Vector3(2, 1, 1), new Vector3(4, 3, 2), 1.3f);
            var reference = ReferenceLighting.FromGrid(grid, sh);
            var pins = Pins.Snap(grid, OffGridPins(grid, 11));
            var tetrahedralizer = new BowyerWatsonDelaunay();
            var order = InsertionOrder.OfValid(grid, sh, reference.SceneScale, null, tetrahedralizer, pins);
            var evaluator = new PlacementEvaluator(reference, tetrahedralizer);
            var settings = new SelectionSettings { Policy = policy, Value = value, KeepBoundsCorners = false };
            var measure = policy == SelectionPolicy.Tolerance ? ReportingMeasure.Wrap(evaluator, grid.Count, null, default) : null;
            var selection = ApplySteps.SelectByInsertion(grid, null, null, order, settings, measure, true, evaluator, null, default, pins);
            Assert.That(pins.Indices.All(selection.Indices.Contains), Is.True);
            Assert.That(selection.Indices.Where(p => !pins.Indices.Contains(p) && pins.Blocked[p]), Is.Empty);
            if (policy == SelectionPolicy.Tolerance) Assert.That(evaluator.MeanError(selection.Indices), Is.LessThanOrEqualTo(value));
            var written = ApplySteps.PositionsOf(grid, selection, pins);
            for (int p = 0; p < pins.Count; p++)
            {
                int k = Array.IndexOf(selection.Indices, pins.Indices[p]);
                Assert.That(written[k].X, Is.EqualTo((float)pins.Positions[p].X), "a pin is written at the artist's position");
            }
        }
    }
}
