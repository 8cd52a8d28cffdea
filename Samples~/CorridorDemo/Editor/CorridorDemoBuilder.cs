using Lpnn.Probes.Editor;
using UnityEditor;
using UnityEditor.SceneManagement;
using UnityEngine;
using UnityEngine.SceneManagement;

namespace Lpnn.Probes.Samples
{
    /// <summary>Builds the thesis' Corridor scene from code: a 24 m corridor with coloured wall panels, baked coloured
    /// point lights, static geometry with colliders, a spawn point (the in-use rule's seed), and an LPNN volume covering
    /// the walkable space, ready for "Run all steps" in its inspector.</summary>
    public static class CorridorDemoBuilder
    {
        public const string MenuPath = "Tools/LPNN Probes/Build Corridor Demo Scene";
        private const float Length = 24f, Width = 3f, Height = 3f, Wall = 0.2f;

        [MenuItem(MenuPath, false, 100)]
        private static void BuildFromMenu()
        {
            if (!EditorSceneManager.SaveCurrentModifiedScenesIfUserWantsTo()) return;
            string path = EditorUtility.SaveFilePanelInProject("Save the corridor demo scene", "CorridorDemo", "unity",
                "Baking needs a saved scene. Pick where the demo scene goes.");
            if (string.IsNullOrEmpty(path)) return;
            var volume = Build(path);
            Selection.activeGameObject = volume.gameObject;
        }

        /// <summary>Creates, fills and saves the demo scene at <paramref name="scenePath"/> (Assets/…/Name.unity);
        /// returns its LPNN volume.</summary>
        public static LpnnVolume Build(string scenePath)
        {
            var scene = EditorSceneManager.NewScene(NewSceneSetup.EmptyScene, NewSceneMode.Single);
            var geometry = new GameObject("Corridor").transform;
            var grey = new Color(0.7f, 0.7f, 0.68f);
            Block(geometry, "Floor", new Vector3(0, -Wall / 2, 0), new Vector3(Width + 2 * Wall, Wall, Length), grey);
            Block(geometry, "Ceiling", new Vector3(0, Height + Wall / 2, 0), new Vector3(Width + 2 * Wall, Wall, Length), grey);
            Block(geometry, "End North", new Vector3(0, Height / 2, Length / 2 + Wall / 2), new Vector3(Width, Height, Wall), grey);
            Block(geometry, "End South", new Vector3(0, Height / 2, -Length / 2 - Wall / 2), new Vector3(Width, Height, Wall), grey);
            // Wall panels in alternating colours, as in the thesis' Corridor scene: colour bleeding the probes must capture.
            Color[] panels = { new Color(0.8f, 0.15f, 0.1f), new Color(0.1f, 0.6f, 0.2f), new Color(0.15f, 0.3f, 0.85f), new Color(0.85f, 0.8f, 0.2f) };
            const int panelCount = 6;
            float panel = Length / panelCount;
            for (int p = 0; p < panelCount; p++)
            {
                float z = -Length / 2 + panel * (p + 0.5f);
                Block(geometry, "Wall West " + p, new Vector3(-Width / 2 - Wall / 2, Height / 2, z), new Vector3(Wall, Height, panel), panels[p % panels.Length]);
                Block(geometry, "Wall East " + p, new Vector3(Width / 2 + Wall / 2, Height / 2, z), new Vector3(Wall, Height, panel), panels[(p + 2) % panels.Length]);
            }
            // A pillar breaks the symmetry and casts shadows.
            Block(geometry, "Pillar", new Vector3(0.6f, Height / 2, 2f), new Vector3(0.4f, Height, 0.4f), grey);

            var lights = new GameObject("Lights").transform;
            Color[] colours = { new Color(1f, 0.55f, 0.2f), new Color(0.3f, 0.8f, 1f), new Color(1f, 0.3f, 0.8f), Color.white };
            for (int l = 0; l < 4; l++)
                PointLight(lights, "Light " + l, new Vector3(l % 2 == 0 ? -0.8f : 0.8f, Height - 0.4f, -9f + 6f * l), colours[l]);

            var volume = LpnnMenuItems.CreateVolume(null);
            volume.transform.position = new Vector3(0, Height / 2, 0);
            volume.SetBoxes(new LpnnBox(Vector3.zero, new Vector3(Width - 0.2f, Height - 0.2f, Length - 0.2f), Vector3.zero));
            volume.SetCellSize(0.5f);
            // Where a character starts: the default in-use rule (Reachable) walks from here over the corridor's floor.
            var spawn = new GameObject("Spawn point").transform;
            spawn.position = new Vector3(0, 0, -Length / 2 + 1.5f);
            volume.SetInUseSeeds(spawn);
            EditorSceneManager.SaveScene(scene, scenePath);
            return volume;
        }

        private static void Block(Transform parent, string name, Vector3 position, Vector3 size, Color colour)
        {
            var block = GameObject.CreatePrimitive(PrimitiveType.Cube); // comes with a BoxCollider, which the rays need
            block.name = name;
            block.transform.SetParent(parent, false);
            block.transform.localPosition = position;
            block.transform.localScale = size;
            // Static for baking: GameObjectUtility.SetStaticEditorFlags (Editor/Mono/GameObjectUtility.bindings.cs).
            GameObjectUtility.SetStaticEditorFlags(block, StaticEditorFlags.ContributeGI | StaticEditorFlags.BatchingStatic);
            var renderer = block.GetComponent<MeshRenderer>();
            var material = new Material(renderer.sharedMaterial) { name = name + " Material" };
            material.color = colour;                  // built-in pipeline (_Color)
            material.SetColor("_BaseColor", colour);  // URP / HDRP Lit
            renderer.sharedMaterial = material;
        }

        private static void PointLight(Transform parent, string name, Vector3 position, Color colour)
        {
            var holder = new GameObject(name);
            holder.transform.SetParent(parent, false);
            holder.transform.localPosition = position;
            var light = holder.AddComponent<Light>();
            light.type = LightType.Point;
            light.color = colour;
            light.intensity = 2.5f;
            light.range = 8f;
            // Light.lightmapBakeType (editor-only setter): Runtime/Export/Graphics/Light.bindings.cs
            light.lightmapBakeType = LightmapBakeType.Baked;
        }
    }
}
