using System;
using System.Collections.Generic;
using System.Linq;
using System.Threading;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Selection;
using Lpnn.Probes.Core.Tests.Support;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    /// <summary>The tolerance search reports progress and honours cancel before each placement-error evaluation (issue 31:
    /// ~20 evaluations, each a tetrahedralisation and a pass over every point, had no progress call).</summary>
    [TestFixture]
    public class ReportingMeasureTests
    {
        /// <summary>An error that falls with the probe count, counting its calls.</summary>
        private sealed class FallingError : IPlacementErrorMeasure
        {
            public int Calls;
            public Action AfterCall;

            public double MeanError(int[] probeIndices)
            {
                Calls++;
                AfterCall?.Invoke();
                return 1.0 / probeIndices.Length;
            }
        }

        private static SelectionResult Search(EvaluationGrid grid, IPlacementErrorMeasure measure)
        {
            var random = new Random(7);
            var scores = Enumerable.Range(0, grid.Count).Select(_ => (float)random.NextDouble()).ToArray();
            return ProbeSelector.Select(new ScoredPoints(grid, scores), SelectionSettings.Tolerance(0.01), measure);
        }

        [Test]
        public void EveryEvaluationReportsProgressWithinTheBound()
        {
            var grid = QualityFixtures.Box(8, 7, 5, 0.5);
            var inner = new FallingError();
            var reports = new List<long>();
            long total = -1;
            var result = Search(grid, ReportingMeasure.Wrap(inner, grid.Count, (stage, done, all) => { reports.Add(done); total = all; }, CancellationToken.None));
            Assert.That(result.Tolerance, Is.Not.Null);
            Assert.That(reports.Count, Is.EqualTo(inner.Calls), "one report per evaluation");
            Assert.That(reports, Is.EqualTo(Enumerable.Range(0, inner.Calls).Select(i => (long)i).ToList()));
            Assert.That(total, Is.EqualTo(ReportingMeasure.MaxEvaluations(grid.Count)));
            Assert.That(inner.Calls, Is.LessThanOrEqualTo(total), "the bound is the search's own");
        }

        [Test]
        public void CancelStopsTheSearchBeforeTheNextEvaluation()
        {
            var grid = QualityFixtures.Box(8, 7, 5, 0.5);
            using (var source = new CancellationTokenSource())
            {
                var inner = new FallingError();
                inner.AfterCall = () => { if (inner.Calls == 2) source.Cancel(); };
                Assert.Throws<OperationCanceledException>(() => Search(grid, ReportingMeasure.Wrap(inner, grid.Count, null, source.Token)));
                Assert.That(inner.Calls, Is.EqualTo(2));
            }
        }

        [TestCase(0, 2)]
        [TestCase(1, 2)]
        [TestCase(2, 4)]
        [TestCase(1000, 22)]
        [TestCase(1024, 22)]
        [TestCase(1025, 24)]
        public void TheBoundIsTwiceTheLogPlusTwo(int candidates, long bound)
        {
            Assert.That(ReportingMeasure.MaxEvaluations(candidates), Is.EqualTo(bound));
        }

        [Test]
        public void NoMeasureStaysNoMeasure()
        {
            Assert.That(ReportingMeasure.Wrap(null, 10, null, CancellationToken.None), Is.Null);
        }
    }
}
