using System;
using System.Numerics;
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
    }
}
