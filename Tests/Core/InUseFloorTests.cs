using System;
using System.Collections.Generic;
using System.Numerics;
using Lpnn.Probes.Core.Captures;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.InUse;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Quality;
using Lpnn.Probes.Core.Tests.Support;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    /// <summary>What the Unity volume adds to the in-use rule: floors from a triangle soup (a baked NavMesh's triangulation,
    /// TriangleFloorRaycaster) with walls from another raycaster (InUseMask.Compute with a floor and a segment raycaster),
    /// the error over the points in use (ErrorSummary.Of with a mask) and the capture's extra section (Capture.WithSection).</summary>
    [TestFixture]
    public class InUseFloorTests
    {
        private static readonly Vector3 Down = new Vector3(0, -1, 0);

        /// <summary>A 4 × 4 m square at height <paramref name="y"/> from x, z = <paramref name="x0"/>, <paramref name="z0"/>, as two triangles.</summary>
        private static void Square(List<Vector3> vertices, List<int> indices, float x0, float z0, float size, float y)
        {
            int first = vertices.Count;
            vertices.Add(new Vector3(x0, y, z0));
            vertices.Add(new Vector3(x0 + size, y, z0));
            vertices.Add(new Vector3(x0 + size, y, z0 + size));
            vertices.Add(new Vector3(x0, y, z0 + size));
            indices.AddRange(new[] { first, first + 1, first + 2, first, first + 2, first + 3 });
        }

        private static RayHit CastDown(IRaycaster raycaster, Vector3 origin, float maxDistance)
        {
            var hits = new[] { RayHit.Miss };
            raycaster.Cast(new[] { origin }, new[] { Down }, maxDistance, hits);
            return hits[0];
        }

        // ------------------------------------------------------------------------------------------ TriangleFloorRaycaster

        [Test]
        public void ADownwardRayFindsTheNearestTriangleBelowWithinTheMaximumDistance()
        {
            var vertices = new List<Vector3>();
            var indices = new List<int>();
            Square(vertices, indices, 0, 0, 4, 0);     // the ground
            Square(vertices, indices, 1, 1, 1, 1.5f);  // a table above part of it
            var floor = new TriangleFloorRaycaster(vertices.ToArray(), indices.ToArray());

            var onGround = CastDown(floor, new Vector3(3, 2, 3), 3);
            Assert.That(onGround.Distance, Is.EqualTo(2f).Within(1e-6f));
            Assert.That(Math.Abs(onGround.Normal.Y), Is.EqualTo(1f).Within(1e-6f));
            Assert.That(CastDown(floor, new Vector3(1.5f, 2, 1.5f), 3).Distance, Is.EqualTo(0.5f).Within(1e-6f), "the table is nearer");
            Assert.That(CastDown(floor, new Vector3(1.5f, 1, 1.5f), 3).Distance, Is.EqualTo(1f).Within(1e-6f), "under the table: the ground");
            Assert.That(CastDown(floor, new Vector3(3, 2, 3), 1.99f).IsHit, Is.False, "beyond the maximum distance");
            Assert.That(CastDown(floor, new Vector3(5, 2, 3), 3).IsHit, Is.False, "beside the ground");
            Assert.That(CastDown(floor, new Vector3(3, -0.5f, 3), 3).IsHit, Is.False, "below the ground: nothing under it");
            Assert.That(CastDown(floor, new Vector3(0.5f, 2, 0.5f), 3).Distance, Is.EqualTo(2f).Within(1e-6f), "on the shared diagonal");
        }

        [Test]
        public void ARampIsHitAtItsHeightWithItsSlopedNormal()
        {
            // A 45° ramp rising along x from (0, 0) to (2, 2), 2 m wide.
            var vertices = new[] { new Vector3(0, 0, 0), new Vector3(2, 2, 0), new Vector3(2, 2, 2), new Vector3(0, 0, 2) };
            var floor = new TriangleFloorRaycaster(vertices, new[] { 0, 1, 2, 0, 2, 3 });
            var hit = CastDown(floor, new Vector3(0.5f, 3, 1), 5);
            Assert.That(hit.Distance, Is.EqualTo(2.5f).Within(1e-6f));
            Assert.That(Math.Abs(hit.Normal.Y), Is.EqualTo((float)Math.Sqrt(0.5)).Within(1e-6f));
            Assert.That(hit.Normal.Length(), Is.EqualTo(1f).Within(1e-6f));
        }

        [Test]
        public void VerticalTrianglesAndEmptySoupsAreNeverHit()
        {
            var wall = new TriangleFloorRaycaster(new[] { new Vector3(0, 0, 0), new Vector3(2, 0, 0), new Vector3(2, 2, 0) }, new[] { 0, 1, 2 });
            Assert.That(CastDown(wall, new Vector3(1.5f, 3, 0), 5).IsHit, Is.False);
            var empty = new TriangleFloorRaycaster(new Vector3[0], new int[0]);
            Assert.That(empty.TriangleCount, Is.EqualTo(0));
            Assert.That(CastDown(empty, new Vector3(0, 1, 0), 5).IsHit, Is.False);
        }

        [Test]
        public void ManyTrianglesInBucketsGiveTheSameHitsAsEveryTriangle()
        {
            // A 40 × 40 terrain of 3,200 triangles (many buckets) against a brute-force search over all of them.
            var vertices = new List<Vector3>();
            var indices = new List<int>();
            const int n = 40;
            for (int z = 0; z <= n; z++)
            for (int x = 0; x <= n; x++)
                vertices.Add(new Vector3(x * 0.5f, (float)(0.3 * Math.Sin(x * 0.7) * Math.Cos(z * 0.4)), z * 0.5f));
            for (int z = 0; z < n; z++)
            for (int x = 0; x < n; x++)
            {
                int a = z * (n + 1) + x;
                indices.AddRange(new[] { a, a + 1, a + n + 2, a, a + n + 2, a + n + 1 });
            }
            var floor = new TriangleFloorRaycaster(vertices.ToArray(), indices.ToArray());
            var singles = new TriangleFloorRaycaster[indices.Count / 3];
            for (int t = 0; t < singles.Length; t++)
                singles[t] = new TriangleFloorRaycaster(vertices.ToArray(), new[] { indices[3 * t], indices[3 * t + 1], indices[3 * t + 2] });
            var random = new Random(7);
            for (int r = 0; r < 200; r++)
            {
                var origin = new Vector3((float)(random.NextDouble() * 21 - 0.5), 2, (float)(random.NextDouble() * 21 - 0.5));
                float expected = float.PositiveInfinity;
                foreach (var single in singles) expected = Math.Min(expected, CastDown(single, origin, 10).Distance);
                Assert.That(CastDown(floor, origin, 10).Distance, Is.EqualTo(expected), "ray " + r + " from " + origin);
            }
        }

        [Test]
        public void OtherDirectionsAndBadTrianglesAreRefusedByName()
        {
            var floor = new TriangleFloorRaycaster(new[] { new Vector3(0, 0, 0), new Vector3(1, 0, 0), new Vector3(0, 0, 1) }, new[] { 0, 1, 2 });
            var sideways = Assert.Throws<ArgumentException>(() =>
                floor.Cast(new[] { Vector3.Zero }, new[] { new Vector3(1, 0, 0) }, 1, new RayHit[1]));
            StringAssert.Contains("straight down only", sideways.Message);
            StringAssert.Contains("index 2 is 3", Assert.Throws<ArgumentException>(() =>
                new TriangleFloorRaycaster(new[] { Vector3.Zero, Vector3.One, Vector3.UnitX }, new[] { 0, 1, 3 })).Message);
            StringAssert.Contains("three indices per triangle", Assert.Throws<ArgumentException>(() =>
                new TriangleFloorRaycaster(new[] { Vector3.Zero }, new[] { 0, 0 })).Message);
            StringAssert.Contains("vertex 1", Assert.Throws<ArgumentException>(() =>
                new TriangleFloorRaycaster(new[] { Vector3.Zero, new Vector3(float.NaN, 0, 0), Vector3.UnitX }, new[] { 0, 1, 2 })).Message);
        }

        // ------------------------------------------------------------------------------------------ floors and walls apart

        /// <summary>Records every ray it is asked to cast, then casts it through the wrapped raycaster.</summary>
        private sealed class RecordingRaycaster : IRaycaster
        {
            private readonly IRaycaster _inner;
            public readonly List<Vector3> Directions = new List<Vector3>();
            public RecordingRaycaster(IRaycaster inner) { _inner = inner; }

            public void Cast(Vector3[] origins, Vector3[] directions, float maxDistance, RayHit[] results)
            {
                Directions.AddRange(directions);
                _inner.Cast(origins, directions, maxDistance, results);
            }
        }

        /// <summary>A row of points 1 m above a floor known only to the triangles, with a wall known only to the boxes: the
        /// band comes from the triangles, the wall stops the walk, and neither raycaster is asked for the other's rays.</summary>
        [Test]
        public void FloorsFromOneRaycasterAndWallsFromAnotherGiveTheWalkOfBoth()
        {
            var vertices = new List<Vector3>();
            var indices = new List<int>();
            Square(vertices, indices, -1, -1, 12, 0);
            var floor = new RecordingRaycaster(new TriangleFloorRaycaster(vertices.ToArray(), indices.ToArray()));
            var boxes = new AnalyticBoxRaycaster();
            boxes.Boxes.Add(new AxisBox(new Double3(4.6, -1, -1), new Double3(4.9, 3, 11)));  // a wall between x = 4.5 and x = 5
            var walls = new RecordingRaycaster(boxes);
            var ids = new List<LatticeId>();
            for (int i = 0; i <= 10; i++) ids.Add(new LatticeId(i, 2, 4));  // x = 0 … 5 m, y = 1 m, z = 2 m
            var grid = EvaluationGrid.FromIds(0.5, ids);
            var seeds = new[] { new Vector3(0.2f, 1, 2) };

            var band = InUseMask.Compute(grid, floor, walls, new InUseParameters(), InUseRule.Band, seeds, null);
            Assert.That(band, Is.All.True, "every point is 1 m above the triangles' floor");
            var reachable = InUseMask.Compute(grid, floor, walls, new InUseParameters(), InUseRule.Reachable, seeds, null);
            for (int n = 0; n < grid.Count; n++)
                Assert.That(reachable[n], Is.EqualTo(grid.GetPosition(n).X < 4.6), "point " + n + " at x = " + grid.GetPosition(n).X);

            Assert.That(floor.Directions, Is.Not.Empty);
            Assert.That(floor.Directions.TrueForAll(d => d == Down), Is.True, "the floor raycaster casts floor rays only");
            Assert.That(walls.Directions, Is.Not.Empty);
            Assert.That(walls.Directions.TrueForAll(d => d.Y == 0), Is.True, "the segment raycaster casts the horizontal segments only");

            // The boxes alone have no floor: one raycaster for both finds no point in band, and says so.
            var noFloor = Assert.Throws<InUseException>(() => InUseMask.Compute(grid, boxes, new InUseParameters(), InUseRule.Band, seeds, null));
            StringAssert.Contains("leaves no point in use", noFloor.Message);
        }

        // ------------------------------------------------------------------------------------------ error at the points in use

        [Test]
        public void TheErrorOverAMaskIsTheSummaryOfTheMaskedValues()
        {
            var values = new[] { 0.5, 0.1, 0.9, 0.3, 0.0 };
            var mask = new[] { false, true, false, true, true };
            var masked = ErrorSummary.Of(values, mask);
            var direct = ErrorSummary.Of(new[] { 0.1, 0.3, 0.0 });
            Assert.That(masked.Mean, Is.EqualTo(direct.Mean));
            Assert.That(masked.P95, Is.EqualTo(direct.P95));
            Assert.That(masked.Mean, Is.EqualTo(0.4 / 3).Within(1e-15));
            Assert.That(ErrorSummary.Of(values, new[] { true, true, true, true, true }).Mean, Is.EqualTo(ErrorSummary.Of(values).Mean));
            StringAssert.Contains("0 of 5", Assert.Throws<PlacementErrorException>(() => ErrorSummary.Of(values, new bool[5])).Message);
            StringAssert.Contains("2 flags for 5 values", Assert.Throws<ArgumentException>(() => ErrorSummary.Of(values, new bool[2])).Message);
        }

        // ------------------------------------------------------------------------------------------ the capture's section

        [Test]
        public void WithSectionKeepsEverythingAndAddsTheSection()
        {
            var capture = new Capture(new[] { 0, 0, 0, 1, 0, 0 }, new float[6], new float[54], new float[2], "schema", new[] { "f" }, 0.5, "m", 1,
                new byte[] { 1, 0 }, "labels", null,
                new[] { new CaptureSection("back_face_fraction", "float32", new[] { 2 }, new byte[8]) });
            var withSection = capture.WithSection(new CaptureSection("in_use", "uint8", new[] { 2 }, new byte[] { 1, 0 }));
            Assert.That(withSection.ExtraSections.Count, Is.EqualTo(2));
            Assert.That(withSection.ExtraSections[0].Name, Is.EqualTo("back_face_fraction"));
            Assert.That(withSection.ExtraSections[1].Name, Is.EqualTo("in_use"));
            Assert.That(withSection.ExtraSections[1].Data, Is.EqualTo(new byte[] { 1, 0 }));
            Assert.That(withSection.Labels, Is.SameAs(capture.Labels));
            Assert.That(withSection.Ids, Is.SameAs(capture.Ids));
            Assert.That(capture.ExtraSections.Count, Is.EqualTo(1), "the original capture is unchanged");
        }
    }
}
