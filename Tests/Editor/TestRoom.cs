using System.Threading;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Sh;
using UnityEditor;
using UnityEditor.SceneManagement;
using UnityEngine;
using NumericsVector3 = System.Numerics.Vector3;

namespace Lpnn.Probes.Editor.Tests
{
    /// <summary>A small scene built from code: a closed 6 × 3 × 4 m room of static boxes with colliders, two coloured
    /// point lights, a ground-truth LightProbeGroup and an LPNN volume filling the room.</summary>
    public sealed class TestRoom
    {
        public LpnnVolume Volume { get; private set; }
        public LightProbeGroup GroundTruth { get; private set; }
        public Light[] Lights { get; private set; }

        public static TestRoom Build()
        {
            EditorSceneManager.NewScene(NewSceneSetup.EmptyScene, NewSceneMode.Single);
            var room = new TestRoom();
            var walls = new GameObject("Room").transform;
            Wall(walls, new Vector3(0, -0.1f, 0), new Vector3(6.4f, 0.2f, 4.4f));
            Wall(walls, new Vector3(0, 3.1f, 0), new Vector3(6.4f, 0.2f, 4.4f));
            Wall(walls, new Vector3(-3.1f, 1.5f, 0), new Vector3(0.2f, 3f, 4f));
            Wall(walls, new Vector3(3.1f, 1.5f, 0), new Vector3(0.2f, 3f, 4f));
            Wall(walls, new Vector3(0, 1.5f, -2.1f), new Vector3(6f, 3f, 0.2f));
            Wall(walls, new Vector3(0, 1.5f, 2.1f), new Vector3(6f, 3f, 0.2f));
            room.Lights = new[] { PointLight("Warm", new Vector3(-2, 2.5f, 0), new Color(1f, 0.5f, 0.2f)), PointLight("Cold", new Vector3(2, 2.5f, 1), new Color(0.2f, 0.5f, 1f)) };

            var truth = new GameObject("Ground truth probes").AddComponent<LightProbeGroup>();
            truth.probePositions = new[] { new Vector3(-2, 1, 0), new Vector3(2, 1, 1), new Vector3(0, 2, -1), new Vector3(0, 0.5f, 1.5f) };
            room.GroundTruth = truth;

            room.Volume = LpnnMenuItems.CreateVolume(null);
            room.Volume.transform.position = new Vector3(0, 1.5f, 0);
            room.Volume.SetBoxes(new LpnnBox(Vector3.zero, new Vector3(5.5f, 2.5f, 3.5f), Vector3.zero));
            room.Volume.SetCellSize(0.5f);
            room.Volume.SetBackend(Core.Scoring.ScoringBackendPreference.Cpu);
            room.Volume.SetGroundTruth(truth);
            // Every point, the volume's behaviour before the in-use rule: these tests are about the other steps (a block inside
            // the room is tested for its interior points, which no character reaches). InUseEditorTests test the rule.
            room.Volume.SetInUseRule(Core.InUse.InUseRule.All);
            return room;
        }

        /// <summary>Analytic lighting from the room's lights (ambient plus one directional term per light, falling off with
        /// distance), so the pipeline test needs no bake and gives the same input on every machine.</summary>
        public IEvaluationLighting AnalyticLighting() => new Analytic(Lights);

        private sealed class Analytic : IEvaluationLighting, ILightSampler
        {
            private readonly Light[] _lights;
            public Analytic(Light[] lights) { _lights = lights; }
            public string Description => "analytic test lighting";

            public float[] Sample(EvaluationGrid grid, ProgressCallback progress, CancellationToken cancel) =>
                FeatureExtractor.SampleLighting(grid, this, progress, cancel);

            public void Sample(NumericsVector3[] positions, float[] sh)
            {
                for (int p = 0; p < positions.Length; p++)
                {
                    int o = p * ShMath.FloatsPerProbe;
                    for (int c = 0; c < ShMath.FloatsPerProbe; c++) sh[o + c] = 0;
                    ShMath.AddAmbient(sh, o, new NumericsVector3(0.02f, 0.02f, 0.02f));
                    foreach (var light in _lights)
                    {
                        var toLight = light.transform.position.ToNumerics() - positions[p];
                        float distance = Mathf.Max(0.25f, toLight.Length());
                        var colour = new NumericsVector3(light.color.r, light.color.g, light.color.b);
                        ShMath.AddDirectional(sh, o, toLight / distance, colour, light.intensity / (distance * distance));
                    }
                }
            }

            public void Dispose() { }
        }

        private static void Wall(Transform parent, Vector3 position, Vector3 size)
        {
            var wall = GameObject.CreatePrimitive(PrimitiveType.Cube);
            wall.transform.SetParent(parent, false);
            wall.transform.localPosition = position;
            wall.transform.localScale = size;
            GameObjectUtility.SetStaticEditorFlags(wall, StaticEditorFlags.ContributeGI);
        }

        private static Light PointLight(string name, Vector3 position, Color colour)
        {
            var light = new GameObject(name).AddComponent<Light>();
            light.type = LightType.Point;
            light.color = colour;
            light.intensity = 2f;
            light.transform.position = position;
            return light;
        }
    }
}
