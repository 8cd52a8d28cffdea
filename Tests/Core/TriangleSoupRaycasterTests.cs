using System;
using System.Numerics;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Tests.Support;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    /// <summary>The Apply benchmark's stand-in for Unity's physics on a real level's triangles (Support/TriangleSoupRaycaster.cs):
    /// hand-checked rays on a wall of two triangles, and the hierarchy's first hits against every triangle tried one by one
    /// by a different test (the plane's crossing, then same-side tests, in double) on random soups. Its agreement with
    /// Embree's answers on a real level's segments is measured, not tested here (benchmarks.md "The C# core under Mono").</summary>
    [TestFixture]
    public class TriangleSoupRaycasterTests
    {
        /// <summary>The unit square x, y in [0, 1] at z = 2, split along its diagonal (0,0)-(1,1).</summary>
        private static TriangleSoupRaycaster Wall() => new TriangleSoupRaycaster(
            new[] { new Double3(0, 0, 2), new Double3(1, 0, 2), new Double3(1, 1, 2), new Double3(0, 1, 2) }, new[] { 0, 1, 2, 0, 2, 3 });

        private static RayHit Cast(IRaycaster rays, Vector3 origin, Vector3 direction, float maxDistance)
        {
            var results = new RayHit[1];
            rays.Cast(new[] { origin }, new[] { Vector3.Normalize(direction) }, maxDistance, results);
            return results[0];
        }

        [Test]
        public void AWallIsHitFromEitherSideWithinTheMaximumDistanceOnly()
        {
            var wall = Wall();
            var front = Cast(wall, new Vector3(0.3f, 0.6f, 0), Vector3.UnitZ, 10);
            Assert.That(front.Distance, Is.EqualTo(2).Within(1e-6));
            Assert.That(Math.Abs(front.Normal.Z), Is.EqualTo(1).Within(1e-6), "the wall's normal, either facing");
            Assert.That(Cast(wall, new Vector3(0.3f, 0.6f, 5), -Vector3.UnitZ, 10).Distance, Is.EqualTo(3).Within(1e-6), "the back face");
            Assert.That(Cast(wall, new Vector3(0.3f, 0.6f, 0), Vector3.UnitZ, 1.9f).IsHit, Is.False, "beyond the maximum distance");
            Assert.That(Cast(wall, new Vector3(0.3f, 0.6f, 0), -Vector3.UnitZ, 10).IsHit, Is.False, "behind the origin");
            Assert.That(Cast(wall, new Vector3(1.5f, 0.5f, 0), Vector3.UnitZ, 10).IsHit, Is.False, "beside the wall");
            Assert.That(Cast(wall, new Vector3(-1, 0.5f, 2), Vector3.UnitX, 10).IsHit, Is.False, "along the wall's plane");
            Assert.That(wall.RaysCast, Is.EqualTo(6));
        }

        [TestCase(0.5f, 0.5f)]  // the diagonal both triangles share
        [TestCase(0f, 0.5f)]  // the square's outer edge
        [TestCase(1f, 1f)]  // a corner
        public void ARayThroughAnEdgeOrCornerHitsTheWall(float x, float y)
        {
            Assert.That(Cast(Wall(), new Vector3(x, y, 0), Vector3.UnitZ, 10).Distance, Is.EqualTo(2).Within(1e-6));
        }

        [Test]
        public void AnEmptySoupHitsNothing()
        {
            var empty = new TriangleSoupRaycaster(new Double3[0], new int[0]);
            Assert.That(Cast(empty, Vector3.Zero, Vector3.UnitX, 100).IsHit, Is.False);
            Assert.Throws<ArgumentException>(() => new TriangleSoupRaycaster(new[] { Double3.Zero }, new[] { 0, 0 }));
            Assert.Throws<ArgumentException>(() => new TriangleSoupRaycaster(new[] { Double3.Zero }, new[] { 0, 0, 1 }));
        }

        [TestCase(1, 40)]
        [TestCase(2, 400)]
        [TestCase(3, 3000)]
        public void TheHierarchyFindsTheFirstHitOfEveryTriangleTriedInTurn(int seed, int triangles)
        {
            var random = new Random(seed);
            var vertices = RandomTriangles(random, triangles, 1, out int[] indices);
            var soup = new TriangleSoupRaycaster(vertices, indices);
            const int rays = 2000;
            const float maxDistance = 15;
            var origins = new Vector3[rays];
            var directions = new Vector3[rays];
            for (int r = 0; r < rays; r++) RandomRay(random, out origins[r], out directions[r]);
            var results = new RayHit[rays];
            soup.Cast(origins, directions, maxDistance, results);
            int hits = 0;
            for (int r = 0; r < rays; r++)
            {
                double expected = FirstHitOneByOne(vertices, triangles, Double3.FromVector3(origins[r]), Double3.FromVector3(directions[r]), maxDistance);
                if (double.IsPositiveInfinity(expected)) Assert.That(results[r].IsHit, Is.False, "ray " + r);
                else
                {
                    hits++;
                    // Float-sized: the raycaster tests in floats, as Embree, with an epsilon at the edges.
                    Assert.That(results[r].Distance, Is.EqualTo(expected).Within(1e-4 * Math.Max(1, expected)), "ray " + r);
                }
            }
            Assert.That(hits, Is.GreaterThan(10), "enough rays hit for the comparison to mean something");
        }

        [Test]
        public void EachRayEndingAtItsOwnDistanceAnswersAsThatRayCastAlone()
        {
            var random = new Random(7);
            const int triangles = 300, rays = 1500;
            var vertices = RandomTriangles(random, triangles, 1.5, out int[] indices);
            var soup = new TriangleSoupRaycaster(vertices, indices);
            var origins = new Vector3[rays];
            var directions = new Vector3[rays];
            var ends = new float[rays];
            for (int r = 0; r < rays; r++)
            {
                RandomRay(random, out origins[r], out directions[r]);
                ends[r] = (float)(20 * random.NextDouble());
            }
            var together = new RayHit[rays];
            soup.Cast(origins, directions, ends, together);
            var far = new RayHit[rays];
            soup.Cast(origins, directions, 20f, far);
            int hits = 0, cut = 0;
            for (int r = 0; r < rays; r++)
            {
                var alone = new RayHit[1];
                soup.Cast(new[] { origins[r] }, new[] { directions[r] }, ends[r], alone);
                Assert.That(together[r].Distance, Is.EqualTo(alone[0].Distance), "ray " + r);
                Assert.That(together[r].Normal, Is.EqualTo(alone[0].Normal), "ray " + r);
                if (together[r].IsHit) hits++;
                if (far[r].IsHit && far[r].Distance > ends[r])
                {
                    cut++;
                    Assert.That(together[r].IsHit, Is.False, "ray " + r + " hits only beyond its own end");
                }
            }
            Assert.That(hits, Is.GreaterThan(20), "enough rays hit within their ends for the comparison to mean something");
            Assert.That(cut, Is.GreaterThan(20), "enough rays hit only beyond their ends");
            Assert.That(soup.RaysCast, Is.EqualTo(3 * rays));
        }

        /// <summary><paramref name="triangles"/> separate triangles, each with its corners within ±<paramref name="halfSize"/>
        /// of a centre in [-10, 10]³; indices 0, 1, 2, ….</summary>
        private static Double3[] RandomTriangles(Random random, int triangles, double halfSize, out int[] indices)
        {
            var vertices = new Double3[3 * triangles];
            indices = new int[3 * triangles];
            for (int t = 0; t < triangles; t++)
            {
                var centre = new Double3(20 * random.NextDouble() - 10, 20 * random.NextDouble() - 10, 20 * random.NextDouble() - 10);
                for (int c = 0; c < 3; c++)
                {
                    vertices[3 * t + c] = centre + new Double3(random.NextDouble() * 2 * halfSize - halfSize,
                        random.NextDouble() * 2 * halfSize - halfSize, random.NextDouble() * 2 * halfSize - halfSize);
                    indices[3 * t + c] = 3 * t + c;
                }
            }
            return vertices;
        }

        /// <summary>A ray from a point drawn in [-12, 12]³ along a direction drawn in [-1, 1]³, normalised (the draws in
        /// that order).</summary>
        private static void RandomRay(Random random, out Vector3 origin, out Vector3 direction)
        {
            origin = new Vector3((float)(24 * random.NextDouble() - 12), (float)(24 * random.NextDouble() - 12), (float)(24 * random.NextDouble() - 12));
            direction = Vector3.Normalize(new Vector3((float)(random.NextDouble() * 2 - 1), (float)(random.NextDouble() * 2 - 1),
                (float)(random.NextDouble() * 2 - 1)));
        }

        /// <summary>The nearest crossing of the ray with a triangle's plane that lies inside the triangle (on the same side of
        /// each edge as the triangle), within <paramref name="maxDistance"/>; +∞ when there is none.</summary>
        private static double FirstHitOneByOne(Double3[] vertices, int triangles, Double3 origin, Double3 direction, double maxDistance)
        {
            double best = double.PositiveInfinity;
            for (int t = 0; t < triangles; t++)
            {
                Double3 a = vertices[3 * t], b = vertices[3 * t + 1], c = vertices[3 * t + 2];
                var normal = Double3.Cross(b - a, c - a);
                double along = Double3.Dot(direction, normal);
                if (along == 0) continue;
                double distance = Double3.Dot(a - origin, normal) / along;
                if (distance < 0 || distance > maxDistance || distance >= best) continue;
                var point = origin + direction * distance;
                if (Double3.Dot(Double3.Cross(b - a, point - a), normal) >= 0 && Double3.Dot(Double3.Cross(c - b, point - b), normal) >= 0 &&
                    Double3.Dot(Double3.Cross(a - c, point - c), normal) >= 0)
                    best = distance;
            }
            return best;
        }
    }
}
