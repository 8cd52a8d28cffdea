using System.Collections.Generic;
using System.Numerics;
using Lpnn.Probes.Core.Captures;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Json;
using Lpnn.Probes.Core.Sh;
using Lpnn.Probes.Core.Tests.Support;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    /// <summary>The shared golden files of Tests/Data: the C# core must reproduce the numbers the Python side is
    /// also pinned to (sh_golden.json is written by Python from the formulas; the rest by Tools~/golden).</summary>
    [TestFixture]
    public class GoldenTests
    {
        private static Vector3 V(JsonValue a) => new Vector3((float)a.Items[0].AsNumber, (float)a.Items[1].AsNumber, (float)a.Items[2].AsNumber);

        [Test]
        public void ShEvaluationMatchesTheFloat64Formulas()
        {
            var golden = TestData.ReadJson("sh_golden.json");
            var tolerance = Tolerance.FromJson(golden);
            foreach (var c in golden.Get("evaluate").Items)
            {
                float[] sh = JsonArrays.Floats(c.Get("sh"));
                var directions = c.Get("directions").Items;
                var expected = c.Get("rgb").Items;
                for (int d = 0; d < directions.Count; d++)
                {
                    var dir = directions[d];
                    ShMath.Evaluate(sh, 0, dir.Items[0].AsNumber, dir.Items[1].AsNumber, dir.Items[2].AsNumber, out double r, out double g, out double b);
                    double[] rgb = { r, g, b };
                    for (int ch = 0; ch < 3; ch++)
                        tolerance.AssertClose(expected[d].Items[ch].AsNumber, rgb[ch], c.Get("name").AsString + " direction " + d);
                }
            }
            foreach (var c in golden.Get("directional").Items)
            {
                var probe = new ShL2();
                probe.AddDirectionalLight(V(c.Get("direction")), V(c.Get("color")), (float)c.Get("intensity").AsNumber);
                float[] actual = probe.ToArray();
                double[] expected = JsonArrays.Doubles(c.Get("sh"));
                for (int i = 0; i < 27; i++) tolerance.AssertClose(expected[i], actual[i], "directional coefficient " + i);
            }
            foreach (var c in golden.Get("ambient_plus_directed").Items)
            {
                var sh = new float[27];
                ShMath.AmbientPlusDirected(V(c.Get("ambient")), V(c.Get("directed")), V(c.Get("direction")), sh, 0);
                double[] expected = JsonArrays.Doubles(c.Get("sh"));
                for (int i = 0; i < 27; i++) tolerance.AssertClose(expected[i], sh[i], "ambient+directed coefficient " + i);
            }
            foreach (var c in golden.Get("luminance").Items)
                tolerance.AssertClose(c.Get("y").AsNumber, ColorSpaces.Luminance(V(c.Get("rgb"))), "luminance");
            foreach (var c in golden.Get("ycocg").Items)
            {
                var actual = ColorSpaces.RgbToYCoCg(V(c.Get("rgb")));
                double[] expected = JsonArrays.Doubles(c.Get("ycocg"));
                tolerance.AssertClose(expected[0], actual.X, "Y");
                tolerance.AssertClose(expected[1], actual.Y, "Co");
                tolerance.AssertClose(expected[2], actual.Z, "Cg");
            }
        }

        private static List<GridBox> Boxes(JsonValue boxes)
        {
            var result = new List<GridBox>();
            foreach (var box in boxes.Items)
            {
                var edges = box.Get("half_edges").Items;
                result.Add(new GridBox(AnalyticScene.ToDouble3(box.Get("center")), AnalyticScene.ToDouble3(edges[0]),
                    AnalyticScene.ToDouble3(edges[1]), AnalyticScene.ToDouble3(edges[2])));
            }
            return result;
        }

        [Test]
        public void GridsMatchTheGoldenPointSets()
        {
            var golden = TestData.ReadJson("grid_golden.json");
            foreach (var c in golden.Get("cases").Items)
            {
                string name = c.Get("name").AsString;
                var grid = GridBuilder.Build(Boxes(c.Get("boxes")), c.Get("cell_size").AsNumber);
                var ids = c.Get("ids").Items;
                Assert.That(grid.Count, Is.EqualTo((int)c.Get("count").AsNumber), name);
                for (int n = 0; n < ids.Count; n++)
                    Assert.That(grid.GetId(n), Is.EqualTo(new LatticeId((int)ids[n].Items[0].AsNumber, (int)ids[n].Items[1].AsNumber, (int)ids[n].Items[2].AsNumber)), name + " point " + n);
            }
            foreach (var c in golden.Get("limit_cases").Items)
            {
                var boxes = Boxes(c.Get("boxes"));
                Assert.That(GridBuilder.CountPoints(boxes, c.Get("cell_size").AsNumber), Is.EqualTo((long)c.Get("count").AsNumber));
                var error = Assert.Throws<GridException>(() => GridBuilder.Build(boxes, c.Get("cell_size").AsNumber, (int)c.Get("point_limit").AsNumber));
                StringAssert.Contains("a cell size of " + Numerics.InvariantFormat.Number(c.Get("fitting_cell_size").AsNumber) + " or larger", error.Message);
            }
        }

        [Test]
        public void FeaturesOfTheAnalyticSceneMatchTheGolden()
        {
            var golden = TestData.ReadJson("features_golden.json");
            var tolerance = Tolerance.FromJson(golden);
            var scene = AnalyticScene.FromJson(golden.Get("scene"));
            var grid = GridBuilder.Build(scene.Boxes, scene.CellSize);
            float[] sh = FeatureExtractor.SampleLighting(grid, scene.Light);
            var features = FeatureExtractor.Extract(grid, sh, scene.Rays);
            var points = golden.Get("points").Items;
            Assert.That(grid.Count, Is.EqualTo(points.Count));
            tolerance.AssertClose(golden.Get("lighting_scale").AsNumber, features.LightingScale, "lighting scale");
            for (int n = 0; n < points.Count; n++)
            {
                var point = points[n];
                var id = point.Get("id").Items;
                Assert.That(grid.GetId(n), Is.EqualTo(new LatticeId((int)id[0].AsNumber, (int)id[1].AsNumber, (int)id[2].AsNumber)));
                double[] expectedSh = JsonArrays.Doubles(point.Get("sh"));
                for (int c = 0; c < 27; c++) tolerance.AssertClose(expectedSh[c], sh[n * 27 + c], "sh of point " + n);
                double[] expected = JsonArrays.Doubles(point.Get("features"));
                for (int f = 0; f < expected.Length; f++)
                    tolerance.AssertClose(expected[f], features[n, f], features.Schema.Names[f] + " of point " + n);
            }
        }

        [Test]
        public void TheGoldenCaptureReadsAsListed()
        {
            var expected = TestData.ReadJson("capture_golden.json");
            var capture = CaptureFile.Read(TestData.PathOf("capture_golden.lpnncap"));
            Assert.That(capture.PointCount, Is.EqualTo((int)expected.Get("point_count").AsNumber));
            Assert.That(capture.Schema, Is.EqualTo(expected.Get("schema").AsString));
            Assert.That(capture.CellSize, Is.EqualTo(expected.Get("cell_size").AsNumber));
            Assert.That(capture.LightingScale, Is.EqualTo(expected.Get("lighting_scale").AsNumber));
            Assert.That(capture.LabelSource, Is.EqualTo(expected.Get("label_source").AsString));
            Assert.That(JsonWriter.Write(capture.Source), Is.EqualTo(JsonWriter.Write(expected.Get("source"))));
            Assert.That(capture.ExtraHeader.Get("future_key").AsString, Is.EqualTo(expected.Get("extra_header").Get("future_key").AsString));
            Assert.That(capture.Sh, Is.EqualTo(JsonArrays.Floats(expected.Get("sh"))));
            Assert.That(capture.Features, Is.EqualTo(JsonArrays.Floats(expected.Get("features"))));
            Assert.That(capture.Positions, Is.EqualTo(JsonArrays.Floats(expected.Get("positions"))));
            var labels = expected.Get("labels").Items;
            for (int n = 0; n < labels.Count; n++) Assert.That(capture.Labels[n], Is.EqualTo((byte)labels[n].AsNumber));
            Assert.That(capture.ExtraSections.Count, Is.EqualTo(1));
            Assert.That(capture.ExtraSections[0].Name, Is.EqualTo("scores"));
            Assert.That(CaptureFile.Encode(capture), Is.EqualTo(System.IO.File.ReadAllBytes(TestData.PathOf("capture_golden.lpnncap"))),
                "re-encoding reproduces the file byte for byte");
        }
    }
}
