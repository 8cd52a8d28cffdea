using System;
using System.Numerics;
using Lpnn.Probes.Core.Batch;
using Lpnn.Probes.Core.Json;
using Lpnn.Probes.Core.Placement;
using Lpnn.Probes.Core.Quality;
using Lpnn.Probes.Core.Tests.Support;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    /// <summary>Batch mode's report of a placement (<see cref="BatchPlacementReport"/>, Documentation~/ci.md "Batch pipeline"):
    /// the pinned count and the inspector's leak line in the log, and the same figures in the probes file's source.</summary>
    [TestFixture]
    public class BatchPlacementReportTests
    {
        /// <summary>3 of 12 points leak, in two tetrahedra (4 probe indices each).</summary>
        private static LeakReport ThreeOfTwelve() => new LeakReport(3, 12, new[] { 0, 1, 2, 3, 1, 2, 3, 4 });

        [Test]
        public void TheLogLineIsTheInspectorsLeakLineAfterThePinnedCount()
        {
            Assert.That(BatchPlacementReport.Of(5, ThreeOfTwelve()).Describe(),
                Is.EqualTo("5 pinned; Leaks: 3 of 12 points in use leak (25 %), in 2 tetrahedra"));
            Assert.That(BatchPlacementReport.Of(0, new LeakReport(1, 1234, new[] { 0, 1, 2, 3 })).Describe(),
                Is.EqualTo("0 pinned; Leaks: 1 of 1,234 points in use leak (0.08 %), in 1 tetrahedron"));
            Assert.That(BatchPlacementReport.Of(0, new LeakReport(0, 40, null), " (every point counted: no floor)").Describe(),
                Is.EqualTo("0 pinned; Leaks: 0 of 40 points in use leak (0 %) (every point counted: no floor)"));
        }

        [Test]
        public void TheProbesFileSourceCarriesThePinnedCountAndTheLeakFigures()
        {
            var source = JsonValue.NewObject();
            source.Set("volume", JsonValue.From("Hall"));
            BatchPlacementReport.Of(5, new LeakReport(1, 3, new[] { 0, 1, 2, 3 })).AddTo(source);
            // Through the file's own writer and reader, as batch mode saves it.
            string text = ProbePositionsFile.Format(new[] { new Vector3(1, 2, 3) }, source);
            var read = ProbePositionsFile.Parse(text, "hall.probes.json").Source;
            Assert.That(read.Get("volume").AsString, Is.EqualTo("Hall"));
            Assert.That(read.Get("pinned").AsNumber, Is.EqualTo(5));
            Assert.That(read.Get("leaking").AsNumber, Is.EqualTo(0.333333), "the share, rounded as lpnn place rounds it");
            Assert.That(read.Get("leaking_points").AsNumber, Is.EqualTo(1));
            Assert.That(read.Get("leak_points_checked").AsNumber, Is.EqualTo(3));
            Assert.That(read.Get("leaking_tetrahedra").AsNumber, Is.EqualTo(1));
            Assert.That(read.Has("leaks_unavailable"), Is.False);
        }

        [Test]
        public void WithoutAReportTheReasonIsWrittenAndNoShare()
        {
            var report = BatchPlacementReport.WithoutLeaks(2, "no lighting for this grid");
            Assert.That(report.Describe(), Is.EqualTo("2 pinned; Leaks unavailable: no lighting for this grid"));
            var source = JsonValue.NewObject();
            report.AddTo(source);
            Assert.That(source.Get("pinned").AsNumber, Is.EqualTo(2));
            Assert.That(source.Get("leaks_unavailable").AsString, Is.EqualTo("no lighting for this grid"));
            Assert.That(source.Has("leaking"), Is.False, "lpnn place leaves the share out when it cannot tell");
        }

        [Test]
        public void AMissingReportOrReasonIsRefused()
        {
            Assert.Throws<ArgumentNullException>(() => BatchPlacementReport.Of(0, null));
            Assert.Throws<ArgumentException>(() => BatchPlacementReport.WithoutLeaks(0, ""));
            Assert.Throws<ArgumentOutOfRangeException>(() => BatchPlacementReport.Of(-1, ThreeOfTwelve()));
        }
    }
}
