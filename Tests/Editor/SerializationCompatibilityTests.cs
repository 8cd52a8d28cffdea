using System.IO;
using System.Linq;
using System.Reflection;
using Lpnn.Probes.Core.Json;
using Lpnn.Probes.Core.Scoring;
using Lpnn.Probes.Core.Selection;
using NUnit.Framework;
using UnityEditor;
using UnityEngine;

namespace Lpnn.Probes.Editor.Tests
{
    /// <summary>A volume saved by version 0.1.0 (Data/LpnnVolume_0.1.0.prefab, written by hand in Unity's text format:
    /// Unity Manual "Format of Text Serialized files") loads with every setting intact (Data/LpnnVolume_0.1.0.expected.json).
    /// Runs only in Unity; make test checks the same fixture against the C# source (field names and their
    /// [FormerlySerializedAs] aliases, enum values: Training~/tests/tools/test_serialized_volume.py). When a serialized
    /// field is renamed, give it [FormerlySerializedAs("oldName")]; enum members are only ever appended.</summary>
    [TestFixture]
    public class SerializationCompatibilityTests
    {
        private const string Folder = "Packages/com.lpnn.probes/Tests/Editor/Data/";

        [Test]
        public void AVolumeSavedByVersion010LoadsWithEverySettingIntact()
        {
            var prefab = AssetDatabase.LoadAssetAtPath<GameObject>(Folder + "LpnnVolume_0.1.0.prefab");
            Assert.That(prefab, Is.Not.Null, "the fixture prefab did not import");
            var volume = prefab.GetComponent<LpnnVolume>();
            Assert.That(volume, Is.Not.Null, "the MonoBehaviour lost its script (LpnnVolume.cs.meta GUID changed?)");
            var expected = JsonParser.Parse(File.ReadAllText(Path.GetFullPath(Folder + "LpnnVolume_0.1.0.expected.json")));
            var values = expected.Get("values");

            var boxes = values.Get("boxes").Items;
            Assert.That(volume.Boxes.Count, Is.EqualTo(boxes.Count));
            for (int b = 0; b < boxes.Count; b++)
            {
                AssertVector(volume.Boxes[b].center, boxes[b].Get("center"));
                AssertVector(volume.Boxes[b].size, boxes[b].Get("size"));
                AssertVector(volume.Boxes[b].rotation, boxes[b].Get("rotation"));
            }
            Assert.That(volume.CellSize, Is.EqualTo(values.Get("cellSize").AsNumber).Within(1e-6));
            Assert.That(volume.PointLimit, Is.EqualTo((int)values.Get("pointLimit").AsNumber));
            Assert.That(volume.AddTemporaryColliders, Is.EqualTo(values.Get("addTemporaryColliders").AsBoolean));
            Assert.That(volume.ScoringPointLimit, Is.EqualTo((int)values.Get("scoringPointLimit").AsNumber));
            Assert.That(volume.DatasetFolder, Is.EqualTo(values.Get("datasetFolder").AsString));
            Assert.That(volume.ShowGizmos, Is.EqualTo(values.Get("showGizmos").AsBoolean));
            Assert.That(volume.Model, Is.Null);
            Assert.That(volume.ModelCard, Is.Null);
            Assert.That(volume.TargetGroup, Is.Null);
            Assert.That(volume.GroundTruthGroup, Is.Null);

            var enums = expected.Get("enums");
            Assert.That(volume.Lighting.ToString(), Is.EqualTo(enums.Get("lightingSource").Get("member").AsString));
            Assert.That(volume.Backend.ToString(), Is.EqualTo(enums.Get("backend").Get("member").AsString));
            Assert.That(volume.Method.ToString(), Is.EqualTo(enums.Get("placementMethod").Get("member").AsString));
            var settings = volume.GetSelectionSettings();
            Assert.That(settings.Policy.ToString(), Is.EqualTo(enums.Get("policy").Get("member").AsString));
            Assert.That(settings.Value, Is.EqualTo(values.Get("budget").AsNumber), "the Spread policy's count is the budget field");
            Assert.That(settings.KeepBoundsCorners, Is.EqualTo(values.Get("keepBoundsCorners").AsBoolean));
            // The other policies' values are kept too (private fields: read by the names the inspector uses).
            foreach (string name in new[] { LpnnVolume.Fields.Percentile, LpnnVolume.Fields.Threshold, LpnnVolume.Fields.Tolerance })
            {
                var field = typeof(LpnnVolume).GetField(name, BindingFlags.Instance | BindingFlags.NonPublic);
                Assert.That((float)field.GetValue(volume), Is.EqualTo(values.Get(name).AsNumber).Within(1e-6), name);
            }

            // Settings added after 0.1.0 load with their defaults (the in-use rule, Documentation~/in-use.md).
            Assert.That(volume.InUseRule, Is.EqualTo(Core.InUse.InUseRules.Default));
            Assert.That(volume.InUseBandHeight, Is.EqualTo((float)Core.InUse.InUseParameters.DefaultBandHeight));
            Assert.That(volume.InUseSlopeLimit, Is.EqualTo((float)Core.InUse.InUseParameters.DefaultSlopeLimitDegrees));
            Assert.That(volume.InUseStepHeight, Is.EqualTo((float)Core.InUse.InUseParameters.DefaultStepHeight));
            Assert.That(volume.InUseSeeds, Is.Empty);
            Assert.That(volume.UseNavMesh, Is.True);

            // The scores 0.1.0 serialized (field "lastScores", issue 31) are not read any more: scores are editor data kept
            // outside the volume (LpnnScores), so this prefab's stored record is ignored and the volume has none.
            Assert.That(values.TryGet("lastScores", out _), Is.True, "the fixture still holds 0.1.0's serialized scores");
            Assert.That(typeof(LpnnVolume).GetField("lastScores", BindingFlags.Instance | BindingFlags.NonPublic | BindingFlags.Public), Is.Null);
            Assert.That(LpnnScores.For(volume).IsEmpty, Is.True);
        }

        private static void AssertVector(Vector3 actual, JsonValue expected)
        {
            var items = expected.Items;
            Assert.That(actual.x, Is.EqualTo(items[0].AsNumber).Within(1e-6));
            Assert.That(actual.y, Is.EqualTo(items[1].AsNumber).Within(1e-6));
            Assert.That(actual.z, Is.EqualTo(items[2].AsNumber).Within(1e-6));
        }
    }

    /// <summary>Reading the expected values: a missing key fails the test with its name.</summary>
    internal static class ExpectedJson
    {
        public static JsonValue Get(this JsonValue value, string key)
        {
            Assert.That(value.TryGet(key, out var found), Is.True, "expected.json has no '" + key + "'");
            return found;
        }
    }
}
