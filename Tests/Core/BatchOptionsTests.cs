using Lpnn.Probes.Core.Batch;
using Lpnn.Probes.Core.Scoring;
using Lpnn.Probes.Core.Selection;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    [TestFixture]
    public class BatchOptionsTests
    {
        [Test]
        public void SkipsUnityArgumentsAndReadsOurs()
        {
            var options = BatchOptions.Parse(new[]
            {
                "Unity", "-batchmode", "-projectPath", "/tmp/p", "-executeMethod", "Lpnn.Probes.Editor.LpnnBatch.Run",
                "-lpnnScene", "Assets/Corridor.unity", "-lpnnMode", "export", "-lpnnOut", "/data/set", "-lpnnBake",
                "-lpnnBackend", "CPU", "-lpnnMethod", "Network", "-lpnnVolume", "LPNN Probes", "-lpnnLabels", "Ground truth", "-logFile", "-",
            });
            Assert.That(options.ScenePath, Is.EqualTo("Assets/Corridor.unity"));
            Assert.That(options.Mode, Is.EqualTo(BatchMode.Export));
            Assert.That(options.OutputFolder, Is.EqualTo("/data/set"));
            Assert.That(options.Bake, Is.True);
            Assert.That(options.Backend, Is.EqualTo(ScoringBackendPreference.Cpu));
            Assert.That(options.VolumeName, Is.EqualTo("LPNN Probes"));
            Assert.That(options.LabelsGroupName, Is.EqualTo("Ground truth"));
            Assert.That(options.SaveScene, Is.False);
            Assert.That(options.Method, Is.EqualTo(PlacementMethod.Network));
        }

        [Test]
        public void DefaultsArePlaceWithoutBakeOnAutoBackend()
        {
            var options = BatchOptions.Parse(new[] { "-lpnnScene", "Assets/A.unity" });
            Assert.That(options.Mode, Is.EqualTo(BatchMode.Place));
            Assert.That(options.Bake, Is.False);
            Assert.That(options.Backend, Is.EqualTo(ScoringBackendPreference.Auto));
            Assert.That(options.OutputFolder, Is.Null);
            Assert.That(options.Method, Is.Null, "no -lpnnMethod: each volume's own method");
        }

        [TestCase("insertion-refined", PlacementMethod.InsertionRefined)]
        [TestCase("insertion", PlacementMethod.Insertion)]
        [TestCase("guided-refined", PlacementMethod.GuidedInsertionRefined)]
        [TestCase("Guided", PlacementMethod.GuidedInsertion)]
        [TestCase("guided", PlacementMethod.GuidedInsertion)]
        [TestCase("network", PlacementMethod.Network)]
        public void MethodNamesParse(string name, PlacementMethod method)
        {
            Assert.That(BatchOptions.Parse(new[] { "-lpnnScene", "A.unity", "-lpnnMethod", name }).Method, Is.EqualTo(method));
        }

        [Test]
        public void EveryMethodHasANameThatParsesBackToIt()
        {
            foreach (PlacementMethod method in System.Enum.GetValues(typeof(PlacementMethod)))
            {
                string name = BatchOptions.MethodName(method);
                Assert.That(BatchOptions.Parse(new[] { "-lpnnScene", "A.unity", "-lpnnMethod", name }).Method, Is.EqualTo(method), name);
                StringAssert.Contains(name, BatchOptions.Usage);
            }
            Assert.That(BatchOptions.MethodName(PlacementMethod.GuidedInsertion), Is.EqualTo("guided"));
            Assert.That(BatchOptions.MethodName(PlacementMethod.InsertionRefined), Is.EqualTo("insertion-refined"));
        }

        [TestCase("fast-reference")]  // a Python-only method of the table
        [TestCase("GuidedInsertion")]  // the enum's name, not the table's
        [TestCase("lpnn-batched")]  // a retired name
        public void AnUnknownMethodIsRefusedListingTheTablesNames(string name)
        {
            var error = Assert.Throws<LpnnException>(() => BatchOptions.Parse(new[] { "-lpnnScene", "A.unity", "-lpnnMethod", name }));
            Assert.That(error.Message, Is.EqualTo("-lpnnMethod '" + name + "' is not a placement method; choose one of " +
                                                  "insertion-refined, insertion, guided-refined, guided, network (Documentation~/methods.md)"));
        }

        [TestCase(new[] { "-lpnnMode", "place" }, "missing -lpnnScene")]
        [TestCase(new[] { "-lpnnScene" }, "-lpnnScene needs a value")]
        [TestCase(new[] { "-lpnnScene", "-lpnnBake" }, "-lpnnScene needs a value")]
        [TestCase(new[] { "-lpnnScene", "A.unity", "-lpnnMode", "train" }, "-lpnnMode 'train' must be place or export")]
        [TestCase(new[] { "-lpnnScene", "A.unity", "-lpnnBackend", "tpu" }, "-lpnnBackend 'tpu' must be auto, gpu or cpu")]
        [TestCase(new[] { "-lpnnScene", "A.unity", "-lpnnMethod", "heuristic" }, "-lpnnMethod 'heuristic' is not a placement method")]
        [TestCase(new[] { "-lpnnScene", "A.unity", "-lpnnMethod", "heuristic" }, "choose one of insertion-refined, insertion, guided-refined")]
        [TestCase(new[] { "-lpnnScene", "A.unity", "-lpnnScenes", "B.unity" }, "unknown argument -lpnnScenes")]
        public void BadArgumentsAreExplained(string[] args, string expected)
        {
            var error = Assert.Throws<LpnnException>(() => BatchOptions.Parse(args));
            StringAssert.Contains(expected, error.Message);
        }
    }
}
