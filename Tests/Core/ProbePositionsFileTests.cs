using System.IO;
using System.Numerics;
using Lpnn.Probes.Core.Json;
using Lpnn.Probes.Core.Placement;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    [TestFixture]
    public class ProbePositionsFileTests
    {
        private string _folder;

        [SetUp]
        public void CreateFolder()
        {
            _folder = Path.Combine(Path.GetTempPath(), "lpnn-probes-" + System.Guid.NewGuid().ToString("N"));
            Directory.CreateDirectory(_folder);
        }

        [TearDown]
        public void DeleteFolder()
        {
            if (Directory.Exists(_folder)) Directory.Delete(_folder, true);
        }

        [Test]
        public void ReadsTheDocumentedExample()
        {
            const string text = "{\"format\": \"lpnn.probes\", \"version\": 1, \"units\": \"m\", \"space\": \"world\", \"count\": 3,\n" +
                                " \"positions\": [[0.5, 1, -2], [1, 1, -2], [1.5, 1, -2]], \"source\": {\"capture\": \"oa_dm1.lpnncap\"}}";
            var content = ProbePositionsFile.Parse(text, "oa_dm1.probes.json");
            Assert.That(content.Positions, Is.EqualTo(new[] { new Vector3(0.5f, 1, -2), new Vector3(1, 1, -2), new Vector3(1.5f, 1, -2) }));
            Assert.That(content.Units, Is.EqualTo("m"));
            Assert.That(content.Source.TryGet("capture", out var capture) ? capture.AsString : null, Is.EqualTo("oa_dm1.lpnncap"));
        }

        [Test]
        public void SaveThenReadRoundTripsExactly()
        {
            var positions = new[] { new Vector3(0.1f, -2.25f, 1e-7f), new Vector3(1234.5f, 0, -0.3f) };
            var source = JsonValue.NewObject();
            source.Set("scene", JsonValue.From("Corridor"));
            string path = Path.Combine(_folder, "corridor" + ProbePositionsFile.Extension);
            ProbePositionsFile.Save(path, positions, source);
            var content = ProbePositionsFile.Read(path);
            Assert.That(content.Positions, Is.EqualTo(positions));
            StringAssert.Contains("\"format\": \"lpnn.probes\", \"version\": 1, \"units\": \"m\", \"space\": \"world\", \"count\": 2", File.ReadAllText(path));
        }

        [TestCase("{\"format\": \"lpnn.capture\", \"version\": 1, \"space\": \"world\", \"positions\": []}", "field 'format' must be \"lpnn.probes\"")]
        [TestCase("{\"format\": \"lpnn.probes\", \"version\": 1, \"space\": \"local\", \"positions\": []}", "field 'space' must be \"world\"")]
        [TestCase("{\"format\": \"lpnn.probes\", \"version\": 1, \"space\": \"world\", \"count\": 2, \"positions\": [[0, 0, 0]]}", "'count' is 2 but 'positions' holds 1")]
        [TestCase("{\"format\": \"lpnn.probes\", \"version\": 1, \"space\": \"world\", \"positions\": [[0, 0, 0], [1, \"a\", 0]]}", "positions[1][1] is not a number")]
        [TestCase("{\"format\": \"lpnn.probes\", \"version\": 1, \"space\": \"world\", \"positions\": [[0, 0]]}", "positions[0] must be a list of 3 numbers")]
        public void InvalidFilesNameTheField(string text, string expected)
        {
            var error = Assert.Throws<LpnnException>(() => ProbePositionsFile.Parse(text, "x.probes.json"));
            StringAssert.Contains("x.probes.json: ", error.Message);
            StringAssert.Contains(expected, error.Message);
        }

        [Test]
        public void NonFinitePositionsAreNeverWritten()
        {
            string path = Path.Combine(_folder, "bad.probes.json");
            Assert.Throws<LpnnException>(() => ProbePositionsFile.Save(path, new[] { new Vector3(float.NaN, 0, 0) }, null));
            Assert.That(File.Exists(path), Is.False);
        }
    }
}
