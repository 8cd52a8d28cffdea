using System;
using System.Collections.Generic;
using System.Globalization;
using System.Text.RegularExpressions;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Numerics;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    [TestFixture]
    public class GridTests
    {
        private static GridBox Box(double x0, double y0, double z0, double x1, double y1, double z1) =>
            GridBox.AxisAligned(new Double3(x0, y0, z0), new Double3(x1, y1, z1));

        private static HashSet<LatticeId> Ids(EvaluationGrid grid)
        {
            var ids = new HashSet<LatticeId>();
            for (int n = 0; n < grid.Count; n++) ids.Add(grid.GetId(n));
            return ids;
        }

        /// <summary>Independent check of the coverage rule: closed cube of the cell vs the closed parallelepiped,
        /// all 15 separating axes, tested point by point over a bounding block.</summary>
        private static HashSet<LatticeId> BruteForce(IEnumerable<GridBox> boxes, double h)
        {
            var result = new HashSet<LatticeId>();
            foreach (var box in boxes)
            {
                var axes = new List<Double3> { new Double3(1, 0, 0), new Double3(0, 1, 0), new Double3(0, 0, 1) };
                var edges = new[] { box.U, box.V, box.W };
                axes.Add(Double3.Cross(box.V, box.W));
                axes.Add(Double3.Cross(box.W, box.U));
                axes.Add(Double3.Cross(box.U, box.V));
                for (int e = 0; e < 3; e++)
                    foreach (var b in edges) axes.Add(Double3.Cross(axes[e], b));
                int[] lo = new int[3], hi = new int[3];
                for (int a = 0; a < 3; a++)
                {
                    double reach = Math.Abs(box.U[a]) + Math.Abs(box.V[a]) + Math.Abs(box.W[a]) + h;
                    lo[a] = (int)Math.Floor((box.Center[a] - reach) / h) - 1;
                    hi[a] = (int)Math.Ceiling((box.Center[a] + reach) / h) + 1;
                }
                for (int k = lo[2]; k <= hi[2]; k++)
                for (int j = lo[1]; j <= hi[1]; j++)
                for (int i = lo[0]; i <= hi[0]; i++)
                {
                    var p = new Double3(h * i, h * j, h * k);
                    bool separated = false;
                    foreach (var a in axes)
                    {
                        if (a.LengthSquared == 0) continue;
                        double boxReach = Math.Abs(Double3.Dot(a, box.U)) + Math.Abs(Double3.Dot(a, box.V)) + Math.Abs(Double3.Dot(a, box.W));
                        double cellReach = h / 2 * (Math.Abs(a.X) + Math.Abs(a.Y) + Math.Abs(a.Z));
                        if (Math.Abs(Double3.Dot(a, p - box.Center)) > boxReach + cellReach) { separated = true; break; }
                    }
                    if (!separated) result.Add(new LatticeId(i, j, k));
                }
            }
            return result;
        }

        [Test]
        public void PointsAreTheCellsThatTouchTheBox()
        {
            var grid = GridBuilder.Build(new[] { Box(0.1, 0.1, 0.1, 0.9, 0.9, 0.9) }, 0.5);
            // x in {0, 0.5, 1}: cells [-.25,.25], [.25,.75], [.75,1.25] all touch [0.1, 0.9]; -0.5 and 1.5 do not.
            Assert.That(grid.Count, Is.EqualTo(27));
            Assert.That(Ids(grid).SetEquals(BruteForce(grid.Boxes, 0.5)), Is.True);
        }

        [Test]
        public void ABoxAlignedWithCellFacesGainsTheNeighbouringLayer()
        {
            // [-0.25, 0.25] is exactly the cell of the origin; the cells of ±0.5 touch it at ±0.25.
            var grid = GridBuilder.Build(new[] { Box(-0.25, -0.25, -0.25, 0.25, 0.25, 0.25) }, 0.5);
            Assert.That(grid.Count, Is.EqualTo(27));
            Assert.That(grid.IndexOf(new LatticeId(-1, -1, -1)), Is.GreaterThanOrEqualTo(0));
        }

        [Test]
        public void PointsComeInGridOrderWithXFastest()
        {
            var grid = GridBuilder.Build(new[] { Box(0, 0, 0, 1, 2, 3) }, 1);
            for (int n = 1; n < grid.Count; n++) Assert.That(grid.GetId(n - 1).CompareTo(grid.GetId(n)), Is.LessThan(0));
            Assert.That(grid.GetId(1), Is.EqualTo(new LatticeId(1, 0, 0)));
            Assert.That(grid.GetPosition(grid.Count - 1).Z, Is.EqualTo(3f));
        }

        [Test]
        public void AddingABoxElsewhereNeverShiftsExistingPoints()
        {
            var first = Box(0.3, 0.3, 0.3, 2.7, 1.9, 1.1);
            var alone = GridBuilder.Build(new[] { first }, 0.4);
            var both = GridBuilder.Build(new[] { first, Box(10.1, -3.3, 5, 12, -1, 7.7) }, 0.4);
            Assert.That(both.Count, Is.GreaterThan(alone.Count));
            for (int n = 0; n < alone.Count; n++)
            {
                int index = both.IndexOf(alone.GetId(n));
                Assert.That(index, Is.GreaterThanOrEqualTo(0));
                Assert.That(both.GetPosition(index), Is.EqualTo(alone.GetPosition(n)));
            }
        }

        [Test]
        public void OverlappingBoxesCountEachPointOnce()
        {
            var a = Box(0, 0, 0, 2, 2, 2);
            var b = Box(1, 1, 1, 3, 3, 3);
            var grid = GridBuilder.Build(new[] { a, b, a }, 1);
            var expected = BruteForce(new[] { a, b }, 1);
            Assert.That(grid.Count, Is.EqualTo(expected.Count));
            Assert.That(GridBuilder.CountPoints(new[] { a, b, a }, 1), Is.EqualTo(expected.Count));
        }

        [TestCase(0.7, 0.3, 0.2, 0.37)]
        [TestCase(0.0, 0.0, 1.2, 0.25)]
        [TestCase(2.1, -0.4, 0.9, 0.5)]
        public void RotatedAndShearedBoxesMatchAPointByPointSeparatingAxisTest(double yaw, double pitch, double shear, double h)
        {
            var rotation = new Func<Double3, Double3>(v =>
            {
                double cy = Math.Cos(yaw), sy = Math.Sin(yaw), cp = Math.Cos(pitch), sp = Math.Sin(pitch);
                var r1 = new Double3(cy * v.X - sy * v.Y, sy * v.X + cy * v.Y, v.Z);
                return new Double3(r1.X, cp * r1.Y - sp * r1.Z, sp * r1.Y + cp * r1.Z);
            });
            var box = new GridBox(new Double3(0.31, -0.77, 1.13), rotation(new Double3(1.7, 0, 0)),
                rotation(new Double3(shear, 0.9, 0)), rotation(new Double3(0, 0.2, 0.45)));
            var grid = GridBuilder.Build(new[] { box }, h);
            var expected = BruteForce(new[] { box }, h);
            Assert.That(Ids(grid).SetEquals(expected), Is.True, "grid has " + grid.Count + " points, brute force " + expected.Count);
        }

        [Test]
        public void DegenerateBoxesStillCoverTheCellsTheyTouch()
        {
            var point = new GridBox(new Double3(0.3, 0.3, 0.3), Double3.Zero, Double3.Zero, Double3.Zero);
            Assert.That(GridBuilder.Build(new[] { point }, 1).Count, Is.EqualTo(1));
            var corner = new GridBox(new Double3(0.5, 0.5, 0.5), Double3.Zero, Double3.Zero, Double3.Zero);
            Assert.That(GridBuilder.Build(new[] { corner }, 1).Count, Is.EqualTo(8), "a point on a cell corner touches 8 cells");
            var flat = Box(0, 0, 0.2, 3, 2, 0.2);
            var flatGrid = GridBuilder.Build(new[] { flat }, 1);
            Assert.That(flatGrid.Count, Is.EqualTo(4 * 3));
            Assert.That(Ids(flatGrid).SetEquals(BruteForce(new[] { flat }, 1)), Is.True);
        }

        [Test]
        public void OneCellSizedBoxFarFromCellFacesGivesOnePoint()
        {
            var grid = GridBuilder.Build(new[] { Box(10.1, 10.1, 10.1, 10.2, 10.2, 10.2) }, 1);
            Assert.That(grid.Count, Is.EqualTo(1));
            Assert.That(grid.GetId(0), Is.EqualTo(new LatticeId(10, 10, 10)));
            Assert.That(grid.Neighbour(0, 0, 1), Is.EqualTo(-1));
        }

        [Test]
        public void AMillionPointsBuildWithWorkingNeighbours()
        {
            var grid = GridBuilder.Build(new[] { Box(0, 0, 0, 100, 100, 100) }, 1);
            Assert.That(grid.Count, Is.EqualTo(101 * 101 * 101));
            int centre = grid.IndexOf(new LatticeId(50, 50, 50));
            Assert.That(grid.GetId(grid.Neighbour(centre, 2, -4)), Is.EqualTo(new LatticeId(50, 50, 46)));
            Assert.That(grid.Neighbour(grid.IndexOf(new LatticeId(100, 0, 0)), 0, 1), Is.EqualTo(-1));
        }

        [Test]
        public void TooManyPointsIsRefusedBeforeAllocatingWithTheCountTheLimitAndACellSizeThatFits()
        {
            var boxes = new[] { Box(0, 0, 0, 100, 100, 100) };
            var error = Assert.Throws<GridException>(() => GridBuilder.Build(boxes, 1, 100000));
            StringAssert.Contains("1,030,301 points", error.Message);
            StringAssert.Contains("limit of 100,000", error.Message);
            StringAssert.Contains("cell size 1", error.Message);
            var match = Regex.Match(error.Message, @"a cell size of ([0-9.]+) or larger would fit");
            Assert.That(match.Success, Is.True, error.Message);
            double fitting = double.Parse(match.Groups[1].Value, CultureInfo.InvariantCulture);
            Assert.That(GridBuilder.CountPoints(boxes, fitting), Is.LessThanOrEqualTo(100000));
            double step = Math.Pow(10, Math.Floor(Math.Log10(fitting)) - 2);
            Assert.That(GridBuilder.CountPoints(boxes, fitting - step), Is.GreaterThan(100000), "the suggestion is the smallest 3-digit size that fits");
        }

        [Test]
        public void AbsurdRowCountsFailFastWithAdvice()
        {
            var boxes = new[] { Box(0, 0, 0, 1000, 1000, 1000) };
            var error = Assert.Throws<GridException>(() => GridBuilder.Build(boxes, 1e-3));
            StringAssert.Contains("candidate grid rows", error.Message);
            var match = Regex.Match(error.Message, @"a cell size of ([0-9.]+) or larger would fit");
            Assert.That(match.Success, Is.True, error.Message);
            double fitting = double.Parse(match.Groups[1].Value, CultureInfo.InvariantCulture);
            Assert.That(GridBuilder.CountPoints(boxes, fitting), Is.LessThanOrEqualTo(GridBuilder.DefaultPointLimit));
            Assert.That(GridBuilder.FittingCellSize(boxes, fitting), Is.Null, "already fits");
        }

        [TestCase(0.0)]
        [TestCase(-0.5)]
        [TestCase(double.NaN)]
        [TestCase(double.PositiveInfinity)]
        public void BadCellSizesAreRejectedNamingTheValue(double cellSize)
        {
            var error = Assert.Throws<GridException>(() => GridBuilder.Build(new[] { Box(0, 0, 0, 1, 1, 1) }, cellSize));
            StringAssert.Contains("cell size " + InvariantFormat.Number(cellSize), error.Message);
        }

        [Test]
        public void NoBoxesOrBadBoxesAreRejected()
        {
            StringAssert.Contains("add at least one box", Assert.Throws<GridException>(() => GridBuilder.Build(new GridBox[0], 1)).Message);
            var nan = new GridBox(new Double3(double.NaN, 0, 0), Double3.Zero, Double3.Zero, Double3.Zero);
            StringAssert.Contains("box 0", Assert.Throws<GridException>(() => GridBuilder.Build(new[] { nan }, 1)).Message);
            Assert.Throws<GridException>(() => Box(1, 0, 0, 0, 1, 1));
        }

        [Test]
        public void LatticeIdsBeyondTwoToTheTwentyThreeAreRefused()
        {
            // 1e6 / 0.1 = 1e7 cells from the origin: beyond 2^23, float32 positions of neighbours may coincide.
            var error = Assert.Throws<GridException>(() => GridBuilder.Build(new[] { Box(1e6, 0, 0, 1e6 + 0.2, 0.1, 0.1) }, 0.1));
            StringAssert.Contains("±2^23", error.Message);
            StringAssert.Contains("float32", error.Message);
        }

        [Test]
        public void FarFromTheOriginIdsStayExactAndPositionsAreTheNearestFloats()
        {
            var grid = GridBuilder.Build(new[] { Box(1e6, -1e6, 5e5, 1e6 + 2, -1e6 + 1, 5e5 + 1) }, 0.5);
            Assert.That(grid.Count, Is.EqualTo(5 * 3 * 3));
            var id = grid.GetId(0);
            Assert.That(id, Is.EqualTo(new LatticeId(2000000, -2000000, 1000000)));
            Assert.That(grid.GetPosition(0).X, Is.EqualTo((float)(0.5 * 2000000)));
            Assert.That(grid.Neighbour(0, 0, 4), Is.EqualTo(4));
        }

        [Test]
        public void TinyAndHugeCellSizes()
        {
            Assert.That(GridBuilder.Build(new[] { Box(0, 0, 0, 0.01, 0.01, 0.01) }, 1e-3).Count, Is.EqualTo(11 * 11 * 11));
            Assert.That(GridBuilder.Build(new[] { Box(0, 0, 0, 1, 1, 1) }, 1e6).Count, Is.EqualTo(1));
        }

        [Test]
        public void FromIdsNamesABadCellSizeWithADotUnderAnyCulture()
        {
            var culture = System.Threading.Thread.CurrentThread.CurrentCulture;
            System.Threading.Thread.CurrentThread.CurrentCulture = new CultureInfo("el-GR");
            try
            {
                var error = Assert.Throws<GridException>(() => EvaluationGrid.FromIds(-0.5, new[] { new LatticeId(0, 0, 0) }));
                StringAssert.StartsWith("cell size -0.5 must", error.Message);
            }
            finally
            {
                System.Threading.Thread.CurrentThread.CurrentCulture = culture;
            }
        }

        [Test]
        public void FromIdsRequiresStrictGridOrderAndSubsetKeepsIt()
        {
            var ids = new[] { new LatticeId(0, 0, 0), new LatticeId(1, 0, 0), new LatticeId(0, 1, 0) };
            var grid = EvaluationGrid.FromIds(0.5, ids);
            Assert.That(grid.Neighbour(0, 1, 1), Is.EqualTo(2));
            var subset = grid.Subset(new[] { true, false, true });
            Assert.That(subset.Count, Is.EqualTo(2));
            Assert.That(subset.GetId(1), Is.EqualTo(new LatticeId(0, 1, 0)));
            var error = Assert.Throws<GridException>(() => EvaluationGrid.FromIds(0.5, new[] { ids[0], ids[2], ids[1] }));
            StringAssert.Contains("point 2 (id 1,0,0) is not after point 1 (id 0,1,0)", error.Message);
            Assert.Throws<GridException>(() => EvaluationGrid.FromIds(0.5, new[] { ids[0], ids[0] }));
            Assert.Throws<GridException>(() => grid.Subset(new[] { false, false, false }));
        }

        [Test]
        public void MemoryEstimateGrowsWithPointsAndFeatures()
        {
            Assert.That(EvaluationGrid.EstimateBytes(1000, 19), Is.EqualTo(1000L * (12 + 12 + 108 + 76 + 4 + 1 + 32 + 168)));
            Assert.That(EvaluationGrid.EstimateBytes(2000000, 19), Is.GreaterThan(int.MaxValue / 8));
        }
    }
}
