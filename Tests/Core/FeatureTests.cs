using System;
using System.Collections.Generic;
using System.Numerics;
using System.Threading;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Sh;
using Lpnn.Probes.Core.Tests.Support;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    [TestFixture]
    public class FeatureTests
    {
        private static readonly FeatureSchema Schema = FeatureSchema.LpnnV1;

        private static int F(string name) => Schema.IndexOf(name);

        /// <summary>A room with two coloured blobs and a pillar: features vary across the grid.</summary>
        private static AnalyticScene BlobRoom()
        {
            var scene = new AnalyticScene { CellSize = 0.5 };
            scene.Boxes.Add(GridBox.AxisAligned(new Double3(0.1, 0.1, 0.1), new Double3(3.9, 2.9, 1.9)));
            scene.Rays.Boxes.Add(new AxisBox(new Double3(-0.37, -0.41, -0.29), new Double3(4.33, 3.27, 2.43)));
            scene.Rays.Boxes.Add(new AxisBox(new Double3(1.61, 1.13, -0.29), new Double3(2.13, 1.71, 1.37)));
            scene.Light.Base[0] = 0.05;
            scene.Light.Base[9] = 0.05;
            scene.Light.Base[18] = 0.06;
            var warm = new double[27];
            warm[0] = 2.0; warm[9] = 1.2; warm[18] = 0.3; warm[3] = 0.8; warm[12] = 0.4; warm[6] = 0.2;
            var cold = new double[27];
            cold[0] = 0.2; cold[9] = 0.6; cold[18] = 1.5; cold[1] = -0.4; cold[19] = -0.9; cold[8] = 0.3;
            scene.Light.Blobs.Add(new LightBlob(new Double3(0.8, 0.7, 1.2), 0.9, warm));
            scene.Light.Blobs.Add(new LightBlob(new Double3(3.1, 2.3, 0.6), 1.3, cold));
            return scene;
        }

        private static FeatureSet Extract(AnalyticScene scene, out EvaluationGrid grid, out float[] sh, double exposure = 1)
        {
            grid = GridBuilder.Build(scene.Boxes, scene.CellSize);
            sh = FeatureExtractor.SampleLighting(grid, scene.Light);
            for (int c = 0; c < sh.Length; c++) sh[c] = (float)(sh[c] * exposure);
            return FeatureExtractor.Extract(grid, sh, scene.Rays);
        }

        [Test]
        public void SchemaNamesAreThePinnedCrossLanguageList()
        {
            var pinned = TestData.ReadJson("schema_lpnn.features.v1.json");
            Assert.That(pinned.Get("schema").AsString, Is.EqualTo(Schema.Id));
            var names = pinned.Get("feature_names").Items;
            Assert.That(names.Count, Is.EqualTo(Schema.Count));
            for (int f = 0; f < names.Count; f++) Assert.That(Schema.Names[f], Is.EqualTo(names[f].AsString));
            Assert.That(FeatureSchema.Thesis30.Count, Is.EqualTo(30));
            Assert.That(FeatureSchema.ById("lpnn.thesis30"), Is.SameAs(FeatureSchema.Thesis30));
            Assert.That(FeatureSchema.ById("unknown"), Is.Null);
        }

        [Test]
        public void DirectionSetsAreUnitAndAntipodal()
        {
            foreach (var set in new[] { DirectionSets.D14, DirectionSets.D26 })
            {
                int count = set.GetLength(0);
                var seen = new HashSet<string>();
                for (int d = 0; d < count; d++)
                {
                    double length = Math.Sqrt(set[d, 0] * set[d, 0] + set[d, 1] * set[d, 1] + set[d, 2] * set[d, 2]);
                    Assert.That(length, Is.EqualTo(1).Within(1e-12));
                    seen.Add(Math.Round(set[d, 0], 6) + "," + Math.Round(set[d, 1], 6) + "," + Math.Round(set[d, 2], 6));
                }
                Assert.That(seen.Count, Is.EqualTo(count), "directions are distinct");
                for (int d = 0; d < count; d++)
                    Assert.That(seen.Contains(Math.Round(-set[d, 0], 6) + "," + Math.Round(-set[d, 1], 6) + "," + Math.Round(-set[d, 2], 6)), Is.True);
            }
        }

        [TestCase(1e-6)]
        [TestCase(1e6)]
        public void EveryFeatureIsInvariantToAGlobalExposureScale(double exposure)
        {
            var scene = BlobRoom();
            var reference = Extract(scene, out _, out _);
            var scaled = Extract(scene, out _, out _, exposure);
            Assert.That(scaled.LightingScale / reference.LightingScale, Is.EqualTo(exposure).Within(exposure * 1e-5));
            for (int v = 0; v < reference.Values.Length; v++)
                Assert.That(scaled.Values[v], Is.EqualTo(reference.Values[v]).Within(2e-4 + 2e-4 * Math.Abs(reference.Values[v])),
                    Schema.Names[v % Schema.Count] + " of point " + v / Schema.Count);
        }

        [Test]
        public void FeaturesVaryWhereTheLightingDoes()
        {
            var features = Extract(BlobRoom(), out var grid, out _);
            double maxCurvature = 0, maxChange = 0;
            for (int n = 0; n < grid.Count; n++)
            {
                maxCurvature = Math.Max(maxCurvature, features[n, F("curvature_1")]);
                maxChange = Math.Max(maxChange, features[n, F("change_1")]);
                for (int f = 0; f < Schema.Count; f++) Assert.That(float.IsNaN(features[n, f]) || float.IsInfinity(features[n, f]), Is.False);
            }
            Assert.That(maxCurvature, Is.GreaterThan(0.01));
            Assert.That(maxChange, Is.GreaterThan(0.05));
        }

        [Test]
        public void ConstantGreyAmbientLightHasNoVariationFeatures()
        {
            var scene = BlobRoom();
            scene.Light.Blobs.Clear();
            scene.Light.Base = new double[27];
            scene.Light.Base[0] = scene.Light.Base[9] = scene.Light.Base[18] = 0.7;
            var features = Extract(scene, out var grid, out _);
            Assert.That(features.LightingScale, Is.EqualTo(0.7).Within(1e-6));
            for (int n = 0; n < grid.Count; n++)
            {
                Assert.That(features[n, F("log_luminance")], Is.EqualTo(Math.Log(1 + 1e-3)).Within(1e-6));
                foreach (string name in new[] { "chroma_co", "chroma_cg", "directionality", "light_variance", "rgb_variance_r",
                             "change_1", "change_2", "change_4", "curvature_1", "curvature_2", "curvature_4" })
                    Assert.That(features[n, F(name)], Is.EqualTo(0).Within(1e-6), name);
            }
        }

        [Test]
        public void LightingThatIsLinearInSpaceHasNoCurvatureButDoesChange()
        {
            // DC grows linearly with x: interpolating a point from its two neighbours is exact.
            var grid = GridBuilder.Build(new[] { GridBox.AxisAligned(new Double3(0, 0, 0), new Double3(8, 2, 2)) }, 1);
            var sh = new float[grid.Count * 27];
            for (int n = 0; n < grid.Count; n++)
            {
                float dc = 1 + 0.5f * grid.GetPosition(n).X;
                sh[n * 27] = dc;
                sh[n * 27 + 9] = 0.5f * dc;
                sh[n * 27 + 18] = 0.25f * dc;
            }
            var features = FeatureExtractor.Extract(grid, sh, new AnalyticBoxRaycaster());
            int centre = grid.IndexOf(new LatticeId(4, 1, 1));
            Assert.That(features[centre, F("curvature_1")], Is.EqualTo(0).Within(1e-6));
            Assert.That(features[centre, F("curvature_4")], Is.EqualTo(0).Within(1e-6));
            Assert.That(features[centre, F("change_1")], Is.GreaterThan(0.05));
            // rel(E(p±k), E(p)) grows with the distance k
            Assert.That(features[centre, F("change_4")], Is.GreaterThan(features[centre, F("change_1")]));
            Assert.That(features[centre, F("curvature_2")], Is.EqualTo(0).Within(1e-6));
        }

        [Test]
        public void BoundaryCountsMissingFaceNeighbours()
        {
            var grid = GridBuilder.Build(new[] { GridBox.AxisAligned(new Double3(0, 0, 0), new Double3(2, 2, 2)) }, 1);
            var sh = new float[grid.Count * 27];
            for (int n = 0; n < grid.Count; n++) sh[n * 27] = 1;
            var features = FeatureExtractor.Extract(grid, sh, new AnalyticBoxRaycaster());
            Assert.That(features[grid.IndexOf(new LatticeId(1, 1, 1)), F("boundary")], Is.EqualTo(0f));
            Assert.That(features[grid.IndexOf(new LatticeId(1, 1, 0)), F("boundary")], Is.EqualTo(1 / 6f).Within(1e-7));
            Assert.That(features[grid.IndexOf(new LatticeId(0, 0, 0)), F("boundary")], Is.EqualTo(0.5f));
        }

        [Test]
        public void GeometryFeaturesMatchTheRoomExactly()
        {
            // h = 1, rays of 4. The room's +x wall is 2.3 from the point at x = 3; other walls are farther than 4.
            var grid = GridBuilder.Build(new[] { GridBox.AxisAligned(new Double3(0, 0, 0), new Double3(3, 0, 0)) }, 1);
            var rays = new AnalyticBoxRaycaster();
            rays.Boxes.Add(new AxisBox(new Double3(-5.3, -5.3, -5.3), new Double3(5.3, 5.3, 5.3)));
            var sh = new float[grid.Count * 27];
            for (int n = 0; n < grid.Count; n++) sh[n * 27] = 1;
            var features = FeatureExtractor.Extract(grid, sh, rays);
            int origin = grid.IndexOf(new LatticeId(0, 0, 0)), near = grid.IndexOf(new LatticeId(3, 0, 0));
            Assert.That(features[origin, F("occlusion_far")], Is.EqualTo(0f));
            Assert.That(features[origin, F("nearest_surface")], Is.EqualTo(1f));
            Assert.That(features[origin, F("normal_spread")], Is.EqualTo(0f));
            // Rays with a +x component reach the wall within 4: the axis (2.3), 4 edges (2.3·√2), 4 diagonals (2.3·√3 = 3.98).
            Assert.That(features[near, F("occlusion_far")], Is.EqualTo(9 / 26f).Within(1e-6));
            Assert.That(features[near, F("occlusion_near")], Is.EqualTo(0f));
            Assert.That(features[near, F("nearest_surface")], Is.EqualTo(2.3f / 4).Within(1e-6));
            Assert.That(features[near, F("normal_spread")], Is.EqualTo(0f).Within(1e-6), "all hits see the same wall");
        }

        [Test]
        public void NormalsAreReorientedSoWindingDoesNotMatter()
        {
            var grid = GridBuilder.Build(new[] { GridBox.AxisAligned(new Double3(0, 0, 0), new Double3(0, 0, 0)) }, 1);
            var sh = new float[27];
            sh[0] = 1;
            var facingAway = new FixedRaycaster(0.5f, new Vector3(1, 0, 0));
            var facingToward = new FixedRaycaster(0.5f, new Vector3(-1, 0, 0));
            var a = FeatureExtractor.Extract(grid, sh, facingAway);
            var b = FeatureExtractor.Extract(grid, sh, facingToward);
            Assert.That(a.Values, Is.EqualTo(b.Values));
            Assert.That(a[0, F("occlusion_near")], Is.EqualTo(1f));
            Assert.That(a[0, F("normal_spread")], Is.GreaterThan(0.5f), "one wall normal per ray direction spreads widely");
        }

        private sealed class FixedRaycaster : IRaycaster
        {
            private readonly float _distance;
            private readonly Vector3 _normal;

            public FixedRaycaster(float distance, Vector3 normal)
            {
                _distance = distance;
                _normal = normal;
            }

            public void Cast(Vector3[] origins, Vector3[] directions, float maxDistance, RayHit[] results)
            {
                for (int r = 0; r < origins.Length; r++)
                {
                    // a "wall" whose normal points along the ray (away) or against it (toward): same surface, other winding
                    var n = _normal.X > 0 ? directions[r] : -directions[r];
                    results[r] = new RayHit { Distance = _distance, Normal = n };
                }
            }
        }

        [Test]
        public void NonFiniteLightingStopsExtractionNamingThePointAndCount()
        {
            var grid = GridBuilder.Build(new[] { GridBox.AxisAligned(new Double3(0, 0, 0), new Double3(2, 0, 0)) }, 1);
            var sh = new float[grid.Count * 27];
            sh[27 + 4] = float.NaN;
            sh[54] = float.PositiveInfinity;
            var error = Assert.Throws<FeatureException>(() => FeatureExtractor.Extract(grid, sh, new AnalyticBoxRaycaster()));
            StringAssert.Contains("2 of 3 evaluation points", error.Message);
            StringAssert.Contains("first at point 1 (id 1,0,0, position (1, 0, 0))", error.Message);
            StringAssert.Contains("re-bake", error.Message);
        }

        [Test]
        public void BadRaycasterOutputIsReported()
        {
            var grid = GridBuilder.Build(new[] { GridBox.AxisAligned(new Double3(0, 0, 0), new Double3(1, 0, 0)) }, 1);
            var sh = new float[grid.Count * 27];
            var error = Assert.Throws<FeatureException>(() => FeatureExtractor.Extract(grid, sh, new FixedRaycaster(float.NaN, Vector3.UnitX)));
            StringAssert.Contains("distance NaN", error.Message);
        }

        [Test]
        public void BlackScenesAreFiniteAndUseScaleOne()
        {
            var grid = GridBuilder.Build(new[] { GridBox.AxisAligned(new Double3(0, 0, 0), new Double3(2, 2, 2)) }, 1);
            var features = FeatureExtractor.Extract(grid, new float[grid.Count * 27], new AnalyticBoxRaycaster());
            Assert.That(features.LightingScale, Is.EqualTo(1.0));
            foreach (float v in features.Values) Assert.That(float.IsNaN(v) || float.IsInfinity(v), Is.False);
            Assert.That(features[0, F("log_luminance")], Is.EqualTo(Math.Log(1e-3)).Within(1e-6));
        }

        [Test]
        public void SceneScaleIsTheMedianOfPositiveLuminances()
        {
            var sh = new float[5 * 27];
            float[] dc = { 0, 1, 3, -2, 5 };
            for (int n = 0; n < 5; n++) sh[n * 27] = sh[n * 27 + 9] = sh[n * 27 + 18] = dc[n];
            Assert.That(SceneScale.Compute(sh, 5), Is.EqualTo(3).Within(1e-9));
            Assert.That(SceneScale.Compute(sh, 3), Is.EqualTo(2).Within(1e-9), "even count: mean of the middle two (1 and 3)");
        }

        [Test]
        public void ExtractionCanBeCancelledAndReportsProgress()
        {
            var scene = BlobRoom();
            var grid = GridBuilder.Build(scene.Boxes, scene.CellSize);
            var sh = FeatureExtractor.SampleLighting(grid, scene.Light);
            var stages = new List<string>();
            long lastDone = -1, lastTotal = -1;
            FeatureExtractor.Extract(grid, sh, scene.Rays, (stage, done, total) =>
            {
                stages.Add(stage);
                lastDone = done;
                lastTotal = total;
            });
            Assert.That(stages, Has.Member("casting rays"));
            Assert.That(lastDone, Is.EqualTo(lastTotal));
            var cancel = new CancellationTokenSource();
            cancel.Cancel();
            Assert.Throws<OperationCanceledException>(() => FeatureExtractor.Extract(grid, sh, scene.Rays, null, cancel.Token));
        }
    }
}
