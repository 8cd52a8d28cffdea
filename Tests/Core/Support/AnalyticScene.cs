using System;
using System.Collections.Generic;
using System.Numerics;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Json;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Sh;

namespace Lpnn.Probes.Core.Tests.Support
{
    /// <summary>The analytic test scene of Tests/Data/README.md: an SH field of Gaussian blobs and exact
    /// axis-aligned walls. Python implements the same text; features_golden.json pins them together.</summary>
    public sealed class AnalyticScene
    {
        public double CellSize;
        public List<GridBox> Boxes = new List<GridBox>();
        public AnalyticLightField Light = new AnalyticLightField();
        public AnalyticBoxRaycaster Rays = new AnalyticBoxRaycaster();

        public static AnalyticScene FromJson(JsonValue json)
        {
            var scene = new AnalyticScene { CellSize = json.Get("cell_size").AsNumber };
            foreach (var box in json.Get("boxes").Items)
            {
                var edges = box.Get("half_edges").Items;
                scene.Boxes.Add(new GridBox(ToDouble3(box.Get("center")), ToDouble3(edges[0]), ToDouble3(edges[1]), ToDouble3(edges[2])));
            }
            var room = json.Get("room");
            scene.Rays.Boxes.Add(new AxisBox(ToDouble3(room.Get("min")), ToDouble3(room.Get("max"))));
            foreach (var obstacle in json.Get("obstacles").Items)
                scene.Rays.Boxes.Add(new AxisBox(ToDouble3(obstacle.Get("min")), ToDouble3(obstacle.Get("max"))));
            var field = json.Get("light_field");
            scene.Light.Base = JsonArrays.Doubles(field.Get("base"));
            foreach (var blob in field.Get("blobs").Items)
                scene.Light.Blobs.Add(new LightBlob(ToDouble3(blob.Get("center")), blob.Get("sigma").AsNumber, JsonArrays.Doubles(blob.Get("sh"))));
            return scene;
        }

        public JsonValue ToJson()
        {
            var json = JsonValue.NewObject();
            json.Set("cell_size", JsonValue.From(CellSize));
            var boxes = JsonValue.NewArray();
            foreach (var box in Boxes)
            {
                var entry = JsonValue.NewObject();
                entry.Set("center", ToJson(box.Center));
                entry.Set("half_edges", JsonValue.ArrayOf(new[] { ToJson(box.U), ToJson(box.V), ToJson(box.W) }));
                boxes.Add(entry);
            }
            json.Set("boxes", boxes);
            json.Set("room", Rays.Boxes[0].ToJson());
            var obstacles = JsonValue.NewArray();
            for (int b = 1; b < Rays.Boxes.Count; b++) obstacles.Add(Rays.Boxes[b].ToJson());
            json.Set("obstacles", obstacles);
            var field = JsonValue.NewObject();
            field.Set("base", Numbers(Light.Base));
            var blobs = JsonValue.NewArray();
            foreach (var blob in Light.Blobs)
            {
                var entry = JsonValue.NewObject();
                entry.Set("center", ToJson(blob.Center));
                entry.Set("sigma", JsonValue.From(blob.Sigma));
                entry.Set("sh", Numbers(blob.Sh));
                blobs.Add(entry);
            }
            field.Set("blobs", blobs);
            json.Set("light_field", field);
            return json;
        }

        public static Double3 ToDouble3(JsonValue array) =>
            new Double3(array.Items[0].AsNumber, array.Items[1].AsNumber, array.Items[2].AsNumber);

        public static JsonValue ToJson(Double3 v) => JsonValue.ArrayOf(new[] { JsonValue.From(v.X), JsonValue.From(v.Y), JsonValue.From(v.Z) });

        public static JsonValue Numbers(IEnumerable<double> values)
        {
            var array = JsonValue.NewArray();
            foreach (double v in values) array.Add(JsonValue.From(v));
            return array;
        }
    }

    public sealed class LightBlob
    {
        public readonly Double3 Center;
        public readonly double Sigma;
        public readonly double[] Sh;

        public LightBlob(Double3 center, double sigma, double[] sh)
        {
            Center = center;
            Sigma = sigma;
            Sh = sh;
        }
    }

    /// <summary>SH(p) = base + Σ sh_b·exp(−|p − c_b|²/σ_b²), in double, rounded to float32.</summary>
    public sealed class AnalyticLightField : ILightSampler
    {
        public double[] Base = new double[ShMath.FloatsPerProbe];
        public List<LightBlob> Blobs = new List<LightBlob>();

        public void Sample(Vector3[] positions, float[] sh)
        {
            var sum = new double[ShMath.FloatsPerProbe];
            for (int n = 0; n < positions.Length; n++)
            {
                var p = Double3.FromVector3(positions[n]);
                Array.Copy(Base, sum, ShMath.FloatsPerProbe);
                foreach (var blob in Blobs)
                {
                    double weight = Math.Exp(-(p - blob.Center).LengthSquared / (blob.Sigma * blob.Sigma));
                    for (int c = 0; c < ShMath.FloatsPerProbe; c++) sum[c] += blob.Sh[c] * weight;
                }
                for (int c = 0; c < ShMath.FloatsPerProbe; c++) sh[n * ShMath.FloatsPerProbe + c] = (float)sum[c];
            }
        }
    }

    public struct AxisBox
    {
        public readonly Double3 Min;
        public readonly Double3 Max;

        public AxisBox(Double3 min, Double3 max)
        {
            Min = min;
            Max = max;
        }

        public JsonValue ToJson()
        {
            var json = JsonValue.NewObject();
            json.Set("min", AnalyticScene.ToJson(Min));
            json.Set("max", AnalyticScene.ToJson(Max));
            return json;
        }

        /// <summary>Slab method in double, tie rules of Tests/Data/README.md; false for a miss.</summary>
        public bool Intersect(Double3 origin, Double3 direction, out double t, out int axis)
        {
            double near = double.NegativeInfinity, far = double.PositiveInfinity;
            int nearAxis = -1, farAxis = -1;
            t = 0;
            axis = -1;
            for (int a = 0; a < 3; a++)
            {
                double o = origin[a], d = direction[a], lo = Min[a], hi = Max[a];
                if (d == 0)
                {
                    if (o < lo || o > hi) return false;
                    continue;
                }
                double inv = 1 / d;
                double t0 = (lo - o) * inv, t1 = (hi - o) * inv;
                double enter = Math.Min(t0, t1), leave = Math.Max(t0, t1);
                if (enter > near) { near = enter; nearAxis = a; }
                if (leave < far) { far = leave; farAxis = a; }
            }
            if (near > far || far < 0) return false;
            if (near < 0)
            {
                t = far;
                axis = farAxis;
            }
            else
            {
                t = near;
                axis = nearAxis;
            }
            return axis >= 0;
        }
    }

    /// <summary>Exact rays against the faces of a room box and obstacle boxes; the smallest t wins (room first).</summary>
    public sealed class AnalyticBoxRaycaster : IRaycaster
    {
        public List<AxisBox> Boxes = new List<AxisBox>();

        public void Cast(Vector3[] origins, Vector3[] directions, float maxDistance, RayHit[] results)
        {
            for (int r = 0; r < origins.Length; r++)
            {
                var origin = Double3.FromVector3(origins[r]);
                var direction = Double3.FromVector3(directions[r]);
                double best = double.PositiveInfinity;
                int bestAxis = -1;
                foreach (var box in Boxes)
                {
                    if (box.Intersect(origin, direction, out double t, out int axis) && t < best)
                    {
                        best = t;
                        bestAxis = axis;
                    }
                }
                if (bestAxis < 0 || !(best <= maxDistance))
                {
                    results[r] = RayHit.Miss;
                    continue;
                }
                var normal = Vector3.Zero;
                float toward = direction[bestAxis] > 0 ? -1f : 1f;
                if (bestAxis == 0) normal.X = toward;
                else if (bestAxis == 1) normal.Y = toward;
                else normal.Z = toward;
                results[r] = new RayHit { Distance = (float)best, Normal = normal };
            }
        }
    }
}
