using System;
using System.Collections.Generic;
using System.Numerics;
using System.Threading;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.InUse;
using Lpnn.Probes.Core.Json;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Quality;
using Lpnn.Probes.Core.Tests.Support;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    /// <summary>Documentation~/leaks.md: the leak rule against Tests/Data/leaks_golden.json (built by construction, the same
    /// cases Python's test_quality_leaks_golden.py reads) and on a placement whose tetrahedra span a wall.</summary>
    [TestFixture]
    public class LeakCheckTests
    {
        private static Vector3 ToVector(JsonValue v) => new Vector3((float)v.Items[0].AsNumber, (float)v.Items[1].AsNumber, (float)v.Items[2].AsNumber);

        private static AnalyticBoxRaycaster Wall()
        {
            var rays = new AnalyticBoxRaycaster();
            rays.Boxes.Add(new AxisBox(new Double3(-0.1, -10, -10), new Double3(0.1, 10, 10)));
            return rays;
        }

        [Test]
        public void EveryGoldenCaseLeaksAsBuilt()
        {
            var golden = TestData.ReadJson("leaks_golden.json");
            Assert.That(golden.Get("minimum_weight").AsNumber, Is.EqualTo(LeakCheck.MinimumWeight));
            var rays = new AnalyticBoxRaycaster();
            foreach (var box in golden.Get("obstacles").Items)
                rays.Boxes.Add(new AxisBox(AnalyticScene.ToDouble3(box.Get("min")), AnalyticScene.ToDouble3(box.Get("max"))));
            var probeItems = golden.Get("probes").Items;
            var probes = new Vector3[probeItems.Count];
            for (int p = 0; p < probes.Length; p++) probes[p] = ToVector(probeItems[p]);
            var cases = golden.Get("cases").Items;
            var points = new Vector3[cases.Count];
            var stencils = new Stencil[cases.Count];
            int leakingCases = 0;
            for (int c = 0; c < cases.Count; c++)
            {
                points[c] = ToVector(cases[c].Get("point"));
                var v = cases[c].Get("vertices").Items;
                var w = cases[c].Get("weights").Items;
                stencils[c] = new Stencil
                {
                    Probe0 = (int)v[0].AsNumber, Probe1 = (int)v[1].AsNumber, Probe2 = (int)v[2].AsNumber, Probe3 = (int)v[3].AsNumber,
                    Weight0 = w[0].AsNumber, Weight1 = w[1].AsNumber, Weight2 = w[2].AsNumber, Weight3 = w[3].AsNumber,
                };
                if (cases[c].Get("leaks").AsBoolean) leakingCases++;
            }
            Assert.That(leakingCases, Is.GreaterThan(0).And.LessThan(cases.Count));
            var leaks = LeakCheck.StencilLeaks(points, probes, stencils, rays);
            for (int c = 0; c < cases.Count; c++)
                Assert.That(leaks[c], Is.EqualTo(cases[c].Get("leaks").AsBoolean), "case " + c);
        }

        [Test]
        public void TetrahedraSpanningAWallLeakAndNothingLeaksWithoutIt()
        {
            // 6 x 6 x 6 points from x = -2.5 to 2.5 (none inside the wall |x| <= 0.1); probes at the 8 corners, so every
            // tetrahedron spans the wall.
            var grid = QualityFixtures.Box(6, 6, 6, 1.0, new Double3(-2.5, 0, 0));
            var positions = QualityFixtures.Positions(grid);
            var reference = ReferenceLighting.Create(positions, QualityFixtures.LinearField(positions, Vector3.Zero));
            int[] probes = QualityFixtures.LatticeProbes(grid, 5);
            int[] tetrahedra = QualityFixtures.KuhnTetrahedra(2, 2, 2);
            var leaking = LeakCheck.Find(reference, probes, tetrahedra, Wall());
            int count = 0;
            foreach (bool leaks in leaking) if (leaks) count++;
            Assert.That(count, Is.GreaterThan(0));
            foreach (int p in probes) Assert.That(leaking[p], Is.False, "a probe never leaks");
            foreach (bool leaks in LeakCheck.Find(reference, probes, tetrahedra, new AnalyticBoxRaycaster()))
                Assert.That(leaks, Is.False, "no wall, no leak");
        }

        [Test]
        public void WeightsOfRoundOffSizeDoNotLeak()
        {
            var points = new[] { new Vector3(-1, 0, 0) };
            var probes = new[] { new Vector3(-2, 0, 0), new Vector3(2, 0, 0), new Vector3(-2, 1, 0), new Vector3(-2, 0, 1) };
            var stencil = new Stencil { Probe0 = 0, Probe1 = 1, Probe2 = 2, Probe3 = 3, Weight0 = 1 - 1e-7, Weight1 = 1e-7 };
            Assert.That(LeakCheck.StencilLeaks(points, probes, new[] { stencil }, Wall())[0], Is.False);
            stencil.Weight0 = 1 - 1e-5;
            stencil.Weight1 = 1e-5;
            Assert.That(LeakCheck.StencilLeaks(points, probes, new[] { stencil }, Wall())[0], Is.True);
        }

        [Test]
        public void SegmentsAreBlockedOnlyBeforeTheirEnd()
        {
            var starts = new[] { new Vector3(-1, 0, 0), new Vector3(-1, 0, 0), new Vector3(-1, 0, 0), new Vector3(0.5f, 0, 0) };
            var ends = new[] { new Vector3(1, 0, 0), new Vector3(-0.2f, 0, 0), new Vector3(-1, 0, 0), new Vector3(3, 0, 0) };
            var free = InUseRays.SegmentsFree(Array.ConvertAll(starts, Double3.FromVector3), Array.ConvertAll(ends, Double3.FromVector3), Wall(),
                "segments", null, System.Threading.CancellationToken.None);
            Assert.That(free, Is.EqualTo(new[] { false, true, true, true }));
        }

        /// <summary>The wall's answers, recording every ray's maximum distance in the order asked.</summary>
        private class RecordingEnds : IRaycaster
        {
            protected readonly AnalyticBoxRaycaster Inner = Wall();
            public readonly List<float> Ends = new List<float>();

            public void Cast(Vector3[] origins, Vector3[] directions, float maxDistance, RayHit[] results)
            {
                for (int r = 0; r < origins.Length; r++) Ends.Add(maxDistance);
                Inner.Cast(origins, directions, maxDistance, results);
            }
        }

        /// <summary>As <see cref="RecordingEnds"/>, also ending each ray at its own distance (one ray per call of the wall).</summary>
        private sealed class RecordingOwnEnds : RecordingEnds, IPerRayDistanceRaycaster
        {
            public void Cast(Vector3[] origins, Vector3[] directions, float[] maxDistances, RayHit[] results)
            {
                var one = new RayHit[1];
                for (int r = 0; r < origins.Length; r++)
                {
                    Ends.Add(maxDistances[r]);
                    Inner.Cast(new[] { origins[r] }, new[] { directions[r] }, maxDistances[r], one);
                    results[r] = one[0];
                }
            }
        }

        [Test]
        public void ARaycasterThatCanEndEachRayCastsEachSegmentToItsOwnLength()
        {
            // Lengths 2, 0.7 (whose nearest float lies below it), 0 (not cast) and 2.5, in double.
            var starts = new[] { new Double3(-1, 0, 0), new Double3(-1, 0, 0), new Double3(-1, 0, 0), new Double3(0.5, 0, 0) };
            var ends = new[] { new Double3(1, 0, 0), new Double3(-1, 0.7, 0), new Double3(-1, 0, 0), new Double3(3, 0, 0) };
            var own = new RecordingOwnEnds();
            var shared = new RecordingEnds();
            var ownFree = InUseRays.SegmentsFree(starts, ends, own, "segments", null, CancellationToken.None);
            var sharedFree = InUseRays.SegmentsFree(starts, ends, shared, "segments", null, CancellationToken.None);
            Assert.That(ownFree, Is.EqualTo(new[] { false, true, true, true }));
            Assert.That(sharedFree, Is.EqualTo(ownFree), "the same answers where no ray grazes a surface");
            Assert.That(shared.Ends, Is.EqualTo(new[] { 2.5f, 2.5f, 2.5f }), "a plain raycaster: the longest segment for every ray");
            Assert.That(own.Ends.Count, Is.EqualTo(3), "the zero-length segment is not cast");
            double[] lengths = { 2, (ends[1] - starts[1]).Length, 2.5 };
            Assert.That((float)lengths[1], Is.LessThan(lengths[1]), "the case where the float must be rounded up");
            for (int r = 0; r < 3; r++)
            {
                // Each ray ends at its segment's length rounded up to a float: not below it, and less than one float step
                // (2^-23 of the binade's bottom) above it.
                double step = Math.Pow(2, Math.Floor(Math.Log(lengths[r], 2)) - 23);
                Assert.That((double)own.Ends[r], Is.GreaterThanOrEqualTo(lengths[r]), "ray " + r);
                Assert.That(own.Ends[r] - lengths[r], Is.LessThan(step), "ray " + r);
            }
        }

        [Test]
        public void EachRayKeepsItsOwnEndAcrossBatches()
        {
            // More segments than one raycaster call takes, each its own length: segment s from (-1, s mod 7 / 7, 0) along +x.
            int count = InUseRays.RaysPerBatch + 500;
            var starts = new Double3[count];
            var ends = new Double3[count];
            for (int s = 0; s < count; s++)
            {
                starts[s] = new Double3(-1, (s % 7) / 7.0, 0);
                ends[s] = starts[s] + new Double3(0.5 + (s % 13) * 0.125, 0, 0);  // 0.5 .. 2: blocked by the wall from 0.9 on
            }
            var own = new RecordingOwnEnds();
            var free = InUseRays.SegmentsFree(starts, ends, own, "segments", null, CancellationToken.None);
            Assert.That(free, Is.EqualTo(InUseRays.SegmentsFree(starts, ends, new RecordingEnds(), "segments", null, CancellationToken.None)));
            Assert.That(own.Ends.Count, Is.EqualTo(count));
            for (int s = 0; s < count; s++)
            {
                double length = 0.5 + (s % 13) * 0.125;  // exact in float
                Assert.That(own.Ends[s], Is.EqualTo((float)length), "segment " + s);
                Assert.That(free[s], Is.EqualTo(length < 0.9), "segment " + s);
            }
        }
    }
}
