using System;
using System.Collections.Generic;
using System.Linq;
using System.Numerics;
using System.Threading;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Selection;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    /// <summary>Points inside solid colliders (Core.Features.InsideColliders; features.md "Probe validity"): the decisions
    /// of the rule on a fake of Unity's overlap and closest-point queries that follows PhysX's semantics per shape.</summary>
    [TestFixture]
    public class InsideCollidersTests
    {
        /// <summary>Analytic colliders with PhysX's overlap semantics: boxes, spheres and height fields are solid; a
        /// "triangle mesh" box is its six faces only (a sphere inside it overlaps nothing).</summary>
        internal sealed class FakeColliders : IColliderQuery
        {
            public sealed class Shape
            {
                public ColliderShape Kind;
                public Vector3 Min, Max;      // Box, TriangleMesh (a closed box mesh), Other (its bounds)
                public Vector3 Centre;        // Sphere
                public float Radius;          // Sphere
                public float Height;          // Heightfield: solid below y = Height
            }

            public readonly List<Shape> Shapes = new List<Shape>();
            public int OverlapCalls, ClosestPointCalls;
            public float LastRadius;

            public FakeColliders Box(Vector3 min, Vector3 max, ColliderShape kind = ColliderShape.Box)
            {
                Shapes.Add(new Shape { Kind = kind, Min = min, Max = max });
                return this;
            }

            public FakeColliders Sphere(Vector3 centre, float radius)
            {
                Shapes.Add(new Shape { Kind = ColliderShape.Sphere, Centre = centre, Radius = radius });
                return this;
            }

            public FakeColliders Terrain(float height)
            {
                Shapes.Add(new Shape { Kind = ColliderShape.Heightfield, Height = height });
                return this;
            }

            public void Overlap(Vector3[] points, float radius, int maxHits, int[] colliders)
            {
                OverlapCalls++;
                LastRadius = radius;
                for (int p = 0; p < points.Length; p++)
                {
                    int h = 0;
                    for (int s = 0; s < Shapes.Count && h < maxHits; s++)
                        if (Overlaps(Shapes[s], points[p], radius)) colliders[p * maxHits + h++] = s + 1;
                }
            }

            private static bool Overlaps(Shape shape, Vector3 p, float radius)
            {
                switch (shape.Kind)
                {
                    case ColliderShape.Sphere: return Vector3.Distance(p, shape.Centre) <= shape.Radius + radius;
                    case ColliderShape.Heightfield: return p.Y <= shape.Height + radius;
                    case ColliderShape.TriangleMesh:
                        // the surface only: within the radius of a face
                        return Vector3.Distance(p, Clamp(p, shape.Min, shape.Max)) <= radius && DistanceToFaces(p, shape) <= radius;
                    default: return Vector3.Distance(p, Clamp(p, shape.Min, shape.Max)) <= radius;
                }
            }

            private static float DistanceToFaces(Vector3 p, Shape box)
            {
                var c = Clamp(p, box.Min, box.Max);
                if (c != p) return Vector3.Distance(p, c);
                return Math.Min(Math.Min(Math.Min(p.X - box.Min.X, box.Max.X - p.X), Math.Min(p.Y - box.Min.Y, box.Max.Y - p.Y)),
                    Math.Min(p.Z - box.Min.Z, box.Max.Z - p.Z));
            }

            private static Vector3 Clamp(Vector3 p, Vector3 min, Vector3 max) => Vector3.Min(Vector3.Max(p, min), max);

            public ColliderShape ShapeOf(int collider) => Shapes[collider - 1].Kind;

            public Vector3 ClosestPoint(int collider, Vector3 point)
            {
                ClosestPointCalls++;
                var shape = Shapes[collider - 1];
                if (shape.Kind == ColliderShape.Sphere)
                {
                    var d = point - shape.Centre;
                    float length = d.Length();
                    return length <= shape.Radius ? point : shape.Centre + d * (shape.Radius / length);
                }
                if (shape.Kind == ColliderShape.Box || shape.Kind == ColliderShape.Capsule || shape.Kind == ColliderShape.ConvexMesh)
                    return Clamp(point, shape.Min, shape.Max);
                throw new InvalidOperationException("Collider.ClosestPoint supports only boxes, spheres, capsules and convex meshes; asked for " + shape.Kind);
            }
        }

        /// <summary>A room's six walls seen from inside (front faces): the rays alone find every point valid.</summary>
        private sealed class OpenRoom : IRaycaster
        {
            public void Cast(Vector3[] origins, Vector3[] directions, float maxDistance, RayHit[] results)
            {
                for (int r = 0; r < origins.Length; r++) results[r] = RayHit.Miss;
            }
        }

        private static EvaluationGrid Grid(double size, double cell) =>
            GridBuilder.Build(new[] { GridBox.AxisAligned(Double3.Zero, new Double3(size, size, size)) }, cell);

        private static float[] FlatSh(EvaluationGrid grid)
        {
            var sh = new float[27 * grid.Count];
            for (int n = 0; n < grid.Count; n++) sh[27 * n] = 1f;
            return sh;
        }

        [Test]
        public void ABoxColliderContainsThePointsInsideAndOnItsBoundaryOnly()
        {
            var colliders = new FakeColliders().Box(new Vector3(1, 1, 1), new Vector3(2, 2, 2));
            var grid = Grid(3, 0.5);
            bool[] inside = InsideColliders.Find(grid, colliders);
            for (int n = 0; n < grid.Count; n++)
            {
                var p = grid.GetPosition(n);
                bool expected = p.X >= 1 && p.X <= 2 && p.Y >= 1 && p.Y <= 2 && p.Z >= 1 && p.Z <= 2;
                Assert.That(inside[n], Is.EqualTo(expected), "point " + p);
            }
            Assert.That(inside.Count(f => f), Is.EqualTo(27), "3 × 3 × 3 points in or on the box");
            Assert.That(colliders.LastRadius, Is.EqualTo((float)(InsideColliders.RadiusCells * 0.5)));
        }

        [Test]
        public void APointJustOutsideASolidIsNotInsideAlthoughTheQuerySphereOverlapsIt()
        {
            float r = InsideColliders.QueryRadius(1);
            var colliders = new FakeColliders().Box(Vector3.Zero, Vector3.One).Sphere(new Vector3(5, 0, 0), 1);
            var points = new[] { new Vector3(1 + r / 2, 0.5f, 0.5f), new Vector3(6 + r / 2, 0, 0), new Vector3(0.5f, 0.5f, 0.5f), new Vector3(5.5f, 0, 0) };
            Assert.That(Find(points, colliders), Is.EqualTo(new[] { false, false, true, true }));
            Assert.That(colliders.ClosestPointCalls, Is.EqualTo(4), "each overlapped solid is confirmed by its closest point");
        }

        [Test]
        public void ANonConvexMeshNeverContainsAPointTheRaysSeeItFromInside()
        {
            // A closed box mesh (a MeshCollider with convex off): PhysX overlaps its triangles only.
            var colliders = new FakeColliders().Box(Vector3.Zero, new Vector3(2, 2, 2), ColliderShape.TriangleMesh);
            Assert.That(Find(new[] { new Vector3(1, 1, 1), new Vector3(0, 1, 1), new Vector3(3, 1, 1) }, colliders), Is.EqualTo(new[] { false, false, false }));
            Assert.That(colliders.ClosestPointCalls, Is.EqualTo(0), "Collider.ClosestPoint is never asked for a non-convex mesh (unsupported there)");
        }

        [Test]
        public void ConvexMeshesAndCapsulesAreSolidLikeBoxes()
        {
            var colliders = new FakeColliders().Box(Vector3.Zero, Vector3.One, ColliderShape.ConvexMesh).Box(new Vector3(3, 0, 0), new Vector3(4, 1, 1), ColliderShape.Capsule);
            Assert.That(Find(new[] { new Vector3(0.5f, 0.5f, 0.5f), new Vector3(3.5f, 0.5f, 0.5f), new Vector3(2, 0.5f, 0.5f) }, colliders),
                Is.EqualTo(new[] { true, true, false }));
        }

        [Test]
        public void BelowATerrainIsInsideAboveItIsNot()
        {
            var colliders = new FakeColliders().Terrain(1f);
            Assert.That(Find(new[] { new Vector3(0, 0.5f, 0), new Vector3(0, 1f, 0), new Vector3(0, 1.01f, 0) }, colliders), Is.EqualTo(new[] { true, true, false }));
            Assert.That(colliders.ClosestPointCalls, Is.EqualTo(0), "the overlap decides for terrain (ClosestPoint does not support it)");
        }

        [Test]
        public void OtherCollidersAreNeverReadAsSolid()
        {
            var colliders = new FakeColliders().Box(Vector3.Zero, Vector3.One, ColliderShape.Other);
            Assert.That(Find(new[] { new Vector3(0.5f, 0.5f, 0.5f) }, colliders), Is.EqualTo(new[] { false }));
        }

        [Test]
        public void ASolidAfterASurfaceHitStillCounts()
        {
            // The point lies on a mesh face (overlapped first, not solid) and inside a box (second hit).
            var colliders = new FakeColliders().Box(Vector3.Zero, Vector3.One, ColliderShape.TriangleMesh).Box(new Vector3(-1, -1, -1), new Vector3(2, 2, 2));
            Assert.That(Find(new[] { new Vector3(0, 0.5f, 0.5f) }, colliders), Is.EqualTo(new[] { true }));
        }

        [Test]
        public void TheClosestPointComparisonAllowsOnlyAFloatRoundTrip()
        {
            var p = new Vector3(1000f, 2f, -3f);
            Assert.That(InsideColliders.IsSamePoint(p, p), Is.True);
            Assert.That(InsideColliders.IsSamePoint(p + new Vector3(1e-4f, 0, 0), p), Is.True, "within a few ulps at 1,000 m");
            Assert.That(InsideColliders.IsSamePoint(p + new Vector3(0, 0.01f, 0), p), Is.False);
            Assert.That(InsideColliders.IsSamePoint(new Vector3(0, 0, 1e-5f), Vector3.Zero), Is.False, "near the origin the tolerance is 1e-6 m");
        }

        [Test]
        public void TheQueryRadiusIsAThousandthOfACell()
        {
            Assert.That(InsideColliders.QueryRadius(0.5), Is.EqualTo(0.0005f));
            Assert.Throws<ArgumentOutOfRangeException>(() => InsideColliders.QueryRadius(0));
            Assert.Throws<ArgumentOutOfRangeException>(() => InsideColliders.QueryRadius(double.NaN));
        }

        [Test]
        public void ANegativeHandleIsAnError()
        {
            var query = new BadHandles();
            StringAssert.Contains("handle -3", Assert.Throws<FeatureException>(() => InsideColliders.Find(Grid(1, 1), query)).Message);
        }

        private sealed class BadHandles : IColliderQuery
        {
            public void Overlap(Vector3[] points, float radius, int maxHits, int[] colliders) => colliders[0] = -3;
            public ColliderShape ShapeOf(int collider) => ColliderShape.Box;
            public Vector3 ClosestPoint(int collider, Vector3 point) => point;
        }

        [Test]
        public void LargeGridsGoInBatchesWithProgressAndCancel()
        {
            var grid = GridBuilder.Build(new[] { GridBox.AxisAligned(Double3.Zero, new Double3(19, 19, 19)) }, 1);  // 8,000 points
            var colliders = new FakeColliders().Box(new Vector3(-0.5f, -0.5f, -0.5f), new Vector3(4.5f, 19.5f, 19.5f));
            var calls = new List<long>();
            bool[] inside = InsideColliders.Find(grid, colliders, (stage, done, total) =>
            {
                Assert.That(stage, Is.EqualTo(InsideColliders.Stage));
                Assert.That(total, Is.EqualTo(grid.Count));
                calls.Add(done);
            });
            Assert.That(colliders.OverlapCalls, Is.EqualTo(2), "4,096 points per batch");
            Assert.That(calls, Is.EqualTo(new long[] { 0, 4096, 8000 }));
            Assert.That(inside.Count(f => f), Is.EqualTo(5 * 20 * 20));
            using (var source = new CancellationTokenSource())
            {
                var counting = new FakeColliders().Box(Vector3.Zero, Vector3.One);
                Assert.Throws(Is.InstanceOf<OperationCanceledException>(),
                    () => InsideColliders.Find(grid, counting, (stage, done, total) => { if (done > 0) source.Cancel(); }, source.Token));
                Assert.That(counting.OverlapCalls, Is.EqualTo(1), "cancel is honoured before the next batch");
            }
        }

        [Test]
        public void FeaturesGiveThePointsInsideASolidColliderBackFaceFractionOneAndMakeThemInvalid()
        {
            // The Corridor sample's case: a BoxCollider pillar; the rays, starting inside it, do not see it.
            var grid = Grid(4, 1);
            var sh = FlatSh(grid);
            var pillar = new FakeColliders().Box(new Vector3(0.5f, -0.5f, 0.5f), new Vector3(1.5f, 4.5f, 1.5f));
            var rays = FeatureExtractor.Extract(grid, sh, new OpenRoom());
            Assert.That(ValidCandidates.CountInvalid(ValidCandidates.FromBackFaceFractions(rays.BackFaceFractions)), Is.EqualTo(0),
                "rays alone: no point is invalid (the issue)");
            Assert.That(rays.InsideColliderCount, Is.EqualTo(0));
            var both = FeatureExtractor.Extract(grid, sh, new OpenRoom(), pillar, null, CancellationToken.None);
            var valid = ValidCandidates.FromBackFaceFractions(both.BackFaceFractions);
            for (int n = 0; n < grid.Count; n++)
            {
                var id = grid.GetId(n);
                bool inPillar = id.I == 1 && id.K == 1;
                Assert.That(valid[n], Is.EqualTo(!inPillar), "point " + id);
                Assert.That(both.BackFaceFractions[n], Is.EqualTo(inPillar ? ProbeValidity.InsideColliderFraction : 0f), "point " + id);
            }
            Assert.That(both.InsideColliderCount, Is.EqualTo(5), "the pillar's column of 5 points");
            Assert.That(both.Values, Is.EqualTo(rays.Values), "the features themselves are the rays'");
            // the capture's validity section carries them, so `lpnn place` drops the same points
            var capture = Lpnn.Probes.Core.Captures.Capture.FromGrid(grid, sh, both);
            int column = Enumerable.Range(0, grid.Count).First(n => grid.GetId(n).I == 1 && grid.GetId(n).K == 1);
            Assert.That(BitConverter.ToSingle(capture.ExtraSections[0].Data, 4 * column), Is.EqualTo(1f));
        }

        private static bool[] Find(Vector3[] points, IColliderQuery colliders) => InsideColliders.Find(points.Length, n => points[n], 1, colliders);
    }
}
