using System.Collections.Generic;
using System.Linq;
using Lpnn.Probes.Core.Scoring;
using Lpnn.Probes.Core.Tests.Support;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    /// <summary>The package the editor would install for each Unity version uses no member that version marks
    /// [Obsolete(..., true)]: a compile error in the installed package stops Unity loading new assemblies, and our compile
    /// check builds only our own code. The uses come from the real sources (Tools~/api-surface/obsolete_uses.py reading
    /// UnityCsReference and needle-mirror/com.unity.ai.inference, com.unity.sentis).</summary>
    [TestFixture]
    public class InferencePackageCompatibilityTests
    {
        private static readonly Dictionary<string, string> NothingInstalled = new Dictionary<string, string>();

        private static IReadOnlyList<string> UsesOfWhatWeWouldInstall(ObsoleteErrorUses table, string unity, string packageToAdd)
        {
            string surface = ObsoleteErrorUses.SurfaceOf(packageToAdd);
            Assert.That(table.WasChecked(unity, surface), Is.True,
                packageToAdd + " for Unity " + unity + " was never checked: add its version to Tools~/api-surface/generate.py and rerun obsolete_uses.py");
            return table.Uses(unity, surface);
        }

        [Test]
        public void EveryCheckedUnityVersionGetsAPackageThatCompilesThere()
        {
            var table = ObsoleteErrorUses.Read();
            Assert.That(table.UnityVersions.ToArray(), Is.EquivalentTo(new[] { "2022.3", "6000.0", "6000.3", "6000.5", "6000.7" }));
            foreach (string unity in table.UnityVersions)
            {
                var decision = InferencePackagePolicy.Decide(unity + ".0f1", NothingInstalled);
                var uses = UsesOfWhatWeWouldInstall(table, unity, decision.PackageToAdd);
                Assert.That(uses, Is.Empty, decision.PackageToAdd + " on Unity " + unity + " uses obsolete-as-error members: " + string.Join("; ", uses));
            }
        }

        /// <summary>The check can fail: the previous choice, 2.4.0 on every 6000.x, is refused on 6000.5 and 6000.7 for the
        /// call the issue names (needle-mirror/com.unity.ai.inference 2.4.0 Editor/Visualizer/Editor/ModelAssetOpenHandler.cs:13).</summary>
        [TestCase("6000.5")]
        [TestCase("6000.7")]
        public void ThePreviousChoiceIsRefused(string unity)
        {
            var uses = UsesOfWhatWeWouldInstall(ObsoleteErrorUses.Read(), unity, "com.unity.ai.inference@2.4.0");
            Assert.That(uses.Any(u => u.StartsWith("Editor/Visualizer/Editor/ModelAssetOpenHandler.cs:13 UnityEditor.EditorUtility.InstanceIDToObject(int)")),
                Is.True, string.Join("; ", uses));
        }

        [Test]
        public void APackageVersionNeverCheckedIsNotTakenAsClean()
        {
            var table = ObsoleteErrorUses.Parse(new[] { "checked unity-6000.5 inference-engine-2.2.2 0" });
            Assert.That(table.WasChecked("6000.5", "inference-engine-2.2.2"), Is.True);
            Assert.That(table.WasChecked("6000.5", "inference-engine-2.5.0"), Is.False);
        }
    }
}
