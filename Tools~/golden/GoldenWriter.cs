using System;
using System.Collections.Generic;
using System.IO;
using Lpnn.Probes.Core.Captures;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Json;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Tests.Support;

namespace Lpnn.Probes.Tools
{
    /// <summary>Writes the C#-side golden files of Tests/Data (grid, features, capture). Run deliberately through
    /// Tools~/regenerate-golden.sh; tests only ever read these files.</summary>
    public static class GoldenWriter
    {
        public static int Main(string[] args)
        {
            string data = args.Length > 0 ? args[0] : "Tests/Data";
            WriteJson(Path.Combine(data, "grid_golden.json"), GridGolden());
            WriteJson(Path.Combine(data, "features_golden.json"), FeaturesGolden());
            WriteCaptureGolden(data);
            Console.WriteLine("wrote grid_golden.json, features_golden.json, capture_golden.lpnncap/.json in " + data);
            return 0;
        }

        private static void WriteJson(string path, JsonValue value) =>
            File.WriteAllText(path, JsonWriter.Write(value, indented: true) + "\n");

        private static GridBox Aabb(double x0, double y0, double z0, double x1, double y1, double z1) =>
            GridBox.AxisAligned(new Double3(x0, y0, z0), new Double3(x1, y1, z1));

        private static Double3 Rotate(Double3 v, double yaw, double pitch)
        {
            double cy = Math.Cos(yaw), sy = Math.Sin(yaw), cp = Math.Cos(pitch), sp = Math.Sin(pitch);
            var r = new Double3(cy * v.X - sy * v.Y, sy * v.X + cy * v.Y, v.Z);
            return new Double3(r.X, cp * r.Y - sp * r.Z, sp * r.Y + cp * r.Z);
        }

        private static JsonValue BoxesJson(IEnumerable<GridBox> boxes)
        {
            var array = JsonValue.NewArray();
            foreach (var box in boxes)
            {
                var entry = JsonValue.NewObject();
                entry.Set("center", AnalyticScene.ToJson(box.Center));
                entry.Set("half_edges", JsonValue.ArrayOf(new[] { AnalyticScene.ToJson(box.U), AnalyticScene.ToJson(box.V), AnalyticScene.ToJson(box.W) }));
                array.Add(entry);
            }
            return array;
        }

        private static JsonValue IdsJson(EvaluationGrid grid)
        {
            var ids = JsonValue.NewArray();
            for (int n = 0; n < grid.Count; n++)
            {
                var id = grid.GetId(n);
                ids.Add(JsonValue.ArrayOf(new[] { JsonValue.From(id.I), JsonValue.From(id.J), JsonValue.From(id.K) }));
            }
            return ids;
        }

        private static JsonValue GridGolden()
        {
            var rotated = new GridBox(new Double3(0.31, -0.77, 1.13), Rotate(new Double3(1.7, 0, 0), 0.7, 0.3),
                Rotate(new Double3(0.2, 0.9, 0), 0.7, 0.3), Rotate(new Double3(0, 0.2, 0.45), 0.7, 0.3));
            var cases = new List<KeyValuePair<string, KeyValuePair<double, GridBox[]>>>
            {
                Case("axis-aligned box inside cells", 0.5, Aabb(0.1, 0.1, 0.1, 0.9, 0.9, 0.9)),
                Case("box faces on cell faces gain the neighbouring layer", 0.5, Aabb(-0.25, -0.25, -0.25, 0.25, 0.25, 0.25)),
                Case("rotated and sheared parallelepiped", 0.37, rotated),
                Case("union of overlapping and disjoint boxes", 1.0, Aabb(0, 0, 0, 2, 2, 2), Aabb(1, 1, 1, 3, 3, 3), Aabb(7.2, -3.4, 0.1, 8.9, -2.2, 0.4)),
                Case("flat box", 1.0, Aabb(0, 0, 0.2, 3, 2, 0.2)),
                Case("point on a cell corner", 1.0, new GridBox(new Double3(0.5, 0.5, 0.5), Double3.Zero, Double3.Zero, Double3.Zero)),
                Case("far from the origin", 0.5, Aabb(1e6, -1e6, 5e5, 1e6 + 2, -1e6 + 1, 5e5 + 1)),
                Case("tiny cells", 1e-3, Aabb(0, 0, 0, 0.004, 0.003, 0.002)),
            };
            var casesJson = JsonValue.NewArray();
            foreach (var c in cases)
            {
                var grid = GridBuilder.Build(c.Value.Value, c.Value.Key);
                var entry = JsonValue.NewObject();
                entry.Set("name", JsonValue.From(c.Key));
                entry.Set("cell_size", JsonValue.From(c.Value.Key));
                entry.Set("boxes", BoxesJson(c.Value.Value));
                entry.Set("count", JsonValue.From(grid.Count));
                entry.Set("ids", IdsJson(grid));
                casesJson.Add(entry);
            }
            var limits = JsonValue.NewArray();
            var big = new[] { Aabb(0, 0, 0, 100, 100, 100) };
            var limit = JsonValue.NewObject();
            limit.Set("name", JsonValue.From("a million points over a limit of 100,000"));
            limit.Set("cell_size", JsonValue.From(1.0));
            limit.Set("boxes", BoxesJson(big));
            limit.Set("point_limit", JsonValue.From(100000));
            limit.Set("count", JsonValue.From(GridBuilder.CountPoints(big, 1.0)));
            limit.Set("fitting_cell_size", JsonValue.From(FittingCellSize(big, 1.0, 100000)));
            limits.Add(limit);
            var golden = JsonValue.NewObject();
            golden.Set("description", JsonValue.From("Evaluation grids (Documentation~/grid.md). Written by Tools~/golden/GoldenWriter.cs."));
            golden.Set("cases", casesJson);
            golden.Set("limit_cases", limits);
            return golden;
        }

        private static KeyValuePair<string, KeyValuePair<double, GridBox[]>> Case(string name, double cell, params GridBox[] boxes) =>
            new KeyValuePair<string, KeyValuePair<double, GridBox[]>>(name, new KeyValuePair<double, GridBox[]>(cell, boxes));

        private static double FittingCellSize(GridBox[] boxes, double cell, int limit)
        {
            try
            {
                GridBuilder.Build(boxes, cell, limit);
            }
            catch (GridException e)
            {
                const string marker = "a cell size of ";
                int start = e.Message.IndexOf(marker, StringComparison.Ordinal) + marker.Length;
                int end = e.Message.IndexOf(' ', start);
                return double.Parse(e.Message.Substring(start, end - start), InvariantFormat.Culture);
            }
            throw new InvalidOperationException("expected the grid to be over the limit");
        }

        /// <summary>The analytic scene: an L-shaped volume (a box and a rotated box), a room with a pillar, and a
        /// light field of a warm and a cold blob with directional terms.</summary>
        private static AnalyticScene GoldenScene()
        {
            var scene = new AnalyticScene { CellSize = 0.5 };
            scene.Boxes.Add(Aabb(0.1, 0.1, 0.1, 4.4, 1.4, 1.4));
            scene.Boxes.Add(new GridBox(new Double3(4.6, 2.2, 0.7), Rotate(new Double3(0.6, 0, 0), 0.52, 0),
                Rotate(new Double3(0, 0.4, 0), 0.52, 0), new Double3(0, 0, 0.5)));
            scene.Rays.Boxes.Add(new AxisBox(new Double3(-0.37, -0.41, -0.29), new Double3(5.83, 3.27, 2.43)));
            scene.Rays.Boxes.Add(new AxisBox(new Double3(1.61, 0.69, -0.29), new Double3(2.17, 1.23, 1.37)));
            scene.Light.Base[0] = 0.05;
            scene.Light.Base[9] = 0.05;
            scene.Light.Base[18] = 0.06;
            var warm = new double[27];
            warm[0] = 2.0; warm[9] = 1.2; warm[18] = 0.3; warm[3] = 0.8; warm[12] = 0.4; warm[21] = 0.1; warm[6] = 0.2; warm[4] = -0.15;
            var cold = new double[27];
            cold[0] = 0.2; cold[9] = 0.6; cold[18] = 1.5; cold[1] = -0.4; cold[19] = -0.9; cold[8] = 0.3; cold[26] = 0.25; cold[14] = -0.1;
            scene.Light.Blobs.Add(new LightBlob(new Double3(0.8, 0.7, 1.2), 0.9, warm));
            scene.Light.Blobs.Add(new LightBlob(new Double3(3.1, 2.3, 0.6), 1.3, cold));
            return scene;
        }

        private static JsonValue FeaturesGolden()
        {
            var scene = GoldenScene();
            var grid = GridBuilder.Build(scene.Boxes, scene.CellSize);
            CheckNoBorderlineRays(scene, grid);
            float[] sh = FeatureExtractor.SampleLighting(grid, scene.Light);
            var features = FeatureExtractor.Extract(grid, sh, scene.Rays);
            var points = JsonValue.NewArray();
            for (int n = 0; n < grid.Count; n++)
            {
                var point = JsonValue.NewObject();
                var id = grid.GetId(n);
                var position = grid.GetPosition(n);
                point.Set("index", JsonValue.From(n));
                point.Set("id", JsonValue.ArrayOf(new[] { JsonValue.From(id.I), JsonValue.From(id.J), JsonValue.From(id.K) }));
                point.Set("position", JsonValue.ArrayOf(new[] { JsonValue.From(position.X), JsonValue.From(position.Y), JsonValue.From(position.Z) }));
                var shValues = new double[27];
                for (int c = 0; c < 27; c++) shValues[c] = sh[n * 27 + c];
                point.Set("sh", AnalyticScene.Numbers(shValues));
                var values = new double[features.Schema.Count];
                for (int f = 0; f < values.Length; f++) values[f] = features[n, f];
                point.Set("features", AnalyticScene.Numbers(values));
                points.Add(point);
            }
            var golden = JsonValue.NewObject();
            golden.Set("description", JsonValue.From("lpnn.features.v1 of every point of the analytic scene (Tests/Data/README.md). Written by Tools~/golden/GoldenWriter.cs."));
            golden.Set("schema", JsonValue.From(features.Schema.Id));
            var names = JsonValue.NewArray();
            foreach (string name in features.Schema.Names) names.Add(JsonValue.From(name));
            golden.Set("feature_names", names);
            var tolerance = JsonValue.NewObject();
            tolerance.Set("abs", JsonValue.From(1e-4));
            tolerance.Set("rel", JsonValue.From(1e-4));
            golden.Set("tolerance", tolerance);
            golden.Set("scene", scene.ToJson());
            golden.Set("lighting_scale", JsonValue.From(features.LightingScale));
            golden.Set("points", points);
            return golden;
        }

        /// <summary>Refuses a scene where a ray sits on a threshold (t within 1e-4 of h or 4h) or grazes an edge
        /// (a tiny tilt flips hit/miss or moves t by more than 1e-3): there, float32 vs float64 rounding
        /// between the languages could change a count.</summary>
        private static void CheckNoBorderlineRays(AnalyticScene scene, EvaluationGrid grid)
        {
            double h = scene.CellSize, far = 4 * h;
            int rays = DirectionSets.D26.GetLength(0);
            var origin = new System.Numerics.Vector3[1];
            var direction = new System.Numerics.Vector3[1];
            var hit = new RayHit[1];
            for (int n = 0; n < grid.Count; n++)
            {
                origin[0] = grid.GetPosition(n);
                for (int d = 0; d < rays; d++)
                {
                    var exact = DirectionSets.Direction(DirectionSets.D26, d);
                    direction[0] = exact;
                    scene.Rays.Cast(origin, direction, (float)(2 * far), hit);
                    double t = hit[0].Distance;
                    if (Math.Abs(t - h) < 1e-4 || Math.Abs(t - far) < 1e-4)
                        throw new InvalidOperationException("point " + n + " ray " + d + " hits at " + t + ", on a feature threshold");
                    foreach (var tilt in new[] { new System.Numerics.Vector3(1e-5f, 2e-5f, -1e-5f), new System.Numerics.Vector3(-2e-5f, 1e-5f, 1e-5f) })
                    {
                        direction[0] = System.Numerics.Vector3.Normalize(exact + tilt);
                        scene.Rays.Cast(origin, direction, (float)(2 * far), hit);
                        double tilted = hit[0].Distance;
                        bool sameKind = double.IsInfinity(t) == double.IsInfinity(tilted);
                        if (!sameKind || (!double.IsInfinity(t) && Math.Abs(t - tilted) > 1e-3))
                            throw new InvalidOperationException("point " + n + " ray " + d + " grazes an edge (t " + t + " vs " + tilted + " when tilted)");
                    }
                }
            }
        }

        private static void WriteCaptureGolden(string data)
        {
            var grid = GridBuilder.Build(new[] { Aabb(0, 0, 0, 1, 1, 0.5) }, 0.5);
            var sh = new float[grid.Count * 27];
            var values = new float[grid.Count * FeatureSchema.LpnnV1.Count];
            for (int n = 0; n < sh.Length; n++) sh[n] = 0.001f * n - 0.2f;
            for (int n = 0; n < values.Length; n++) values[n] = (float)Math.Sin(n) * 0.0226f;
            var labels = new byte[grid.Count];
            labels[3] = labels[7] = 1;
            var source = JsonValue.NewObject();
            source.Set("scene", JsonValue.From("golden room"));
            source.Set("backend", JsonValue.From("synthetic"));
            var extraHeader = JsonValue.NewObject();
            extraHeader.Set("future_key", JsonValue.From("readers keep unknown keys"));
            var scores = new float[grid.Count];
            for (int n = 0; n < scores.Length; n++) scores[n] = n / (float)grid.Count;
            var scoreBytes = new byte[scores.Length * 4];
            Buffer.BlockCopy(scores, 0, scoreBytes, 0, scoreBytes.Length);
            var capture = new Capture(grid.CopyIds(), grid.CopyPositions(), sh, values, FeatureSchema.LpnnV1.Id, FeatureSchema.LpnnV1.Names,
                grid.CellSize, "m", 0.125, labels, "probes:golden", source,
                new[] { new CaptureSection("scores", "float32", new[] { grid.Count }, scoreBytes) }, extraHeader);
            CaptureFile.Save(Path.Combine(data, "capture_golden.lpnncap"), capture);

            var expected = JsonValue.NewObject();
            expected.Set("description", JsonValue.From("What a reader must find in capture_golden.lpnncap. Written by Tools~/golden/GoldenWriter.cs."));
            expected.Set("point_count", JsonValue.From(capture.PointCount));
            expected.Set("schema", JsonValue.From(capture.Schema));
            expected.Set("cell_size", JsonValue.From(capture.CellSize));
            expected.Set("units", JsonValue.From(capture.Units));
            expected.Set("lighting_scale", JsonValue.From(capture.LightingScale));
            expected.Set("label_source", JsonValue.From(capture.LabelSource));
            expected.Set("source", source);
            expected.Set("extra_header", extraHeader);
            expected.Set("ids", IdsJson(grid));
            expected.Set("positions", Floats(capture.Positions));
            expected.Set("sh", Floats(capture.Sh));
            expected.Set("features", Floats(capture.Features));
            var labelJson = JsonValue.NewArray();
            foreach (byte label in labels) labelJson.Add(JsonValue.From(label));
            expected.Set("labels", labelJson);
            expected.Set("extra_section_scores", Floats(scores));
            WriteJson(Path.Combine(data, "capture_golden.json"), expected);
        }

        private static JsonValue Floats(float[] values)
        {
            var array = JsonValue.NewArray();
            foreach (float v in values) array.Add(JsonValue.From(v));
            return array;
        }
    }
}
