using System;
using System.Numerics;
using System.Threading;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Quality;
using Lpnn.Probes.Core.Tests.Support;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    /// <summary>The inspector's leak report (Documentation~/leaks.md "What is reported"): the share over the points in use
    /// and the tetrahedra holding a leaking point, against LeakCheck.Find and an exact box raycaster.</summary>
    [TestFixture]
    public class LeakReportTests
    {
        private static AnalyticBoxRaycaster Wall()
        {
            var rays = new AnalyticBoxRaycaster();
            rays.Boxes.Add(new AxisBox(new Double3(-0.1, -10, -10), new Double3(0.1, 10, 10)));
            return rays;
        }

        private static void Scene(out ReferenceLighting reference, out int[] probes, out int[] tetrahedra)
        {
            // As LeakCheckTests: 6 x 6 x 6 points from x = -2.5 to 2.5, probes at the 8 corners, every tetrahedron spans the wall.
            var grid = QualityFixtures.Box(6, 6, 6, 1.0, new Double3(-2.5, 0, 0));
            var positions = QualityFixtures.Positions(grid);
            reference = ReferenceLighting.Create(positions, QualityFixtures.LinearField(positions, Vector3.Zero));
            probes = QualityFixtures.LatticeProbes(grid, 5);
            tetrahedra = QualityFixtures.KuhnTetrahedra(2, 2, 2);
        }

        [Test]
        public void CountsTheLeakingPointsAsLeakCheckFindsThem()
        {
            Scene(out var reference, out var probes, out var tetrahedra);
            var expected = LeakCheck.Find(reference, probes, tetrahedra, Wall());
            var report = LeakReport.Compute(reference, probes, tetrahedra, null, Wall(), null, CancellationToken.None);
            Assert.That(report.Points, Is.EqualTo(reference.Count));
            Assert.That(report.Leaking, Is.EqualTo(LeakReport.CountTrue(expected, null)));
            Assert.That(report.Leaking, Is.GreaterThan(0).And.LessThan(report.Points));
            Assert.That(report.TetrahedronCount, Is.GreaterThan(0).And.AtMost(tetrahedra.Length / 4));
            foreach (int v in report.LeakingTetrahedra) Assert.That(v, Is.InRange(0, probes.Length - 1));
        }

        [Test]
        public void CountsOnlyThePointsInUse()
        {
            Scene(out var reference, out var probes, out var tetrahedra);
            var all = LeakCheck.Find(reference, probes, tetrahedra, Wall());
            // In use: the left half (x < 0) plus every probe.
            var mask = new bool[reference.Count];
            for (int n = 0; n < mask.Length; n++) mask[n] = reference.GetPosition(n).X < 0;
            foreach (int p in probes) mask[p] = true;
            var report = LeakReport.Compute(reference, probes, tetrahedra, mask, Wall(), null, CancellationToken.None);
            int inUse = LeakReport.CountTrue(mask, null);
            Assert.That(report.Points, Is.EqualTo(inUse));
            Assert.That(report.Leaking, Is.EqualTo(LeakReport.CountTrue(all, mask)));
            Assert.That(report.Leaking, Is.LessThan(LeakReport.CountTrue(all, null)));
            Assert.That(report.Fraction, Is.EqualTo((double)report.Leaking / inUse).Within(1e-12));
        }

        [Test]
        public void NothingLeaksWithoutAWall()
        {
            Scene(out var reference, out var probes, out var tetrahedra);
            var report = LeakReport.Compute(reference, probes, tetrahedra, null, new AnalyticBoxRaycaster(), null, CancellationToken.None);
            Assert.That(report.Leaking, Is.EqualTo(0));
            Assert.That(report.TetrahedronCount, Is.EqualTo(0));
            Assert.That(report.Describe(), Is.EqualTo("0 of " + reference.Count + " points in use leak (0 %)"));
        }

        [Test]
        public void CellsHoldingAreTheDistinctCellsOfLeakingPoints()
        {
            var cells = new[] { 3, 1, 3, 0, 2, -1 };
            var leaks = new[] { true, false, true, true, false, true };
            Assert.That(LeakReport.CellsHolding(cells, leaks), Is.EqualTo(new[] { 0, 3 }));
            Assert.Throws<ArgumentException>(() => LeakReport.CellsHolding(cells, new bool[2]));
        }

        [Test]
        public void VerticesAreTheCellsCorners()
        {
            var tetrahedra = new[] { 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11 };
            Assert.That(LeakReport.Vertices(tetrahedra, new[] { 2, 0 }), Is.EqualTo(new[] { 8, 9, 10, 11, 0, 1, 2, 3 }));
            Assert.Throws<ArgumentOutOfRangeException>(() => LeakReport.Vertices(tetrahedra, new[] { 3 }));
        }

        [Test]
        public void DescribesTheShare()
        {
            Assert.That(new LeakReport(12, 3456, null).Describe(), Is.EqualTo("12 of 3,456 points in use leak (0.35 %)"));
            Assert.Throws<ArgumentOutOfRangeException>(() => new LeakReport(5, 4, null));
        }

        [Test]
        public void CancelStopsTheRays()
        {
            Scene(out var reference, out var probes, out var tetrahedra);
            var source = new CancellationTokenSource();
            source.Cancel();
            Assert.Throws<OperationCanceledException>(() =>
                LeakReport.Compute(reference, probes, tetrahedra, null, Wall(), null, source.Token));
        }
    }
}
