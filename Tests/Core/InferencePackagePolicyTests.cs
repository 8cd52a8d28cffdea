using System.Collections.Generic;
using Lpnn.Probes.Core.Scoring;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    /// <summary>Every supported project ends with exactly one .onnx importer: the policy adds the package of the editor's
    /// version when none is installed, removes Sentis when both are, and leaves a supported single package alone.</summary>
    [TestFixture]
    public class InferencePackagePolicyTests
    {
        private static Dictionary<string, string> Installed(params string[] nameVersion)
        {
            var installed = new Dictionary<string, string>();
            for (int i = 0; i + 1 < nameVersion.Length; i += 2) installed[nameVersion[i]] = nameVersion[i + 1];
            return installed;
        }

        [TestCase("2022.3.11f1", "com.unity.sentis@2.1.3")]
        [TestCase("2022.3.62f2", "com.unity.sentis@2.1.3")]
        [TestCase("6000.0.23f1", "com.unity.ai.inference@2.4.0")]
        [TestCase("6000.3.0f1", "com.unity.ai.inference@2.4.0")]
        [TestCase("6000.4.9f1", "com.unity.ai.inference@2.4.0")]
        [TestCase("6000.5.0f1", "com.unity.ai.inference@2.2.2")]
        [TestCase("6000.7.0a1", "com.unity.ai.inference@2.2.2")]
        [TestCase("6000.10.0a1", "com.unity.ai.inference@2.2.2")]
        [TestCase("7000.0.0a1", "com.unity.ai.inference@2.2.2")]
        public void WithoutAPackageTheEditorsOwnIsAdded(string unity, string expected)
        {
            var decision = InferencePackagePolicy.Decide(unity, Installed());
            Assert.That(decision.Action, Is.EqualTo(InferencePackageAction.Add));
            Assert.That(decision.PackageToAdd, Is.EqualTo(expected));
        }

        [TestCase("2022.3.11f1")]
        [TestCase("6000.0.23f1")]
        public void BothPackagesMeanRemovingSentis(string unity)
        {
            var decision = InferencePackagePolicy.Decide(unity, Installed("com.unity.sentis", "2.1.3", "com.unity.ai.inference", "2.2.1"));
            Assert.That(decision.Action, Is.EqualTo(InferencePackageAction.RemoveSentis));
            Assert.That(decision.Package, Is.EqualTo("com.unity.sentis"));
            Assert.That(decision.PackageToAdd, Is.EqualTo(""));
            StringAssert.Contains("importer", decision.Message);
        }

        [Test]
        public void AnIndirectSentisBesideInferenceEngineIsLeftToTheUser()
        {
            var decision = InferencePackagePolicy.Decide("6000.0.23f1", Installed("com.unity.sentis", "2.1.3", "com.unity.ai.inference", "2.2.1"),
                sentisIsDirect: false);
            Assert.That(decision.Action, Is.EqualTo(InferencePackageAction.ResolveByHand));
            Assert.That(decision.PackageToAdd, Is.EqualTo(""));
            StringAssert.Contains("dependency of another package", decision.Message);
        }

        [TestCase("2022.3.11f1", "com.unity.sentis", "2.1.3")]
        [TestCase("6000.0.23f1", "com.unity.sentis", "2.1.0")]
        [TestCase("6000.0.23f1", "com.unity.ai.inference", "2.2.0")]
        [TestCase("6000.3.2f1", "com.unity.ai.inference", "2.4.0")]
        [TestCase("6000.5.2f1", "com.unity.ai.inference", "2.2.2")]
        [TestCase("6000.5.2f1", "com.unity.ai.inference", "2.2.1-pre.1")]
        public void OneSupportedPackageIsLeftAlone(string unity, string name, string version)
        {
            var decision = InferencePackagePolicy.Decide(unity, Installed(name, version));
            Assert.That(decision.Action, Is.EqualTo(InferencePackageAction.Ready));
        }

        [TestCase("2022.3.11f1", "com.unity.sentis", "1.6.0-pre.1", "com.unity.sentis@2.1.3")]
        [TestCase("6000.0.23f1", "com.unity.sentis", "1.4.0", "com.unity.ai.inference@2.4.0")]
        [TestCase("6000.0.23f1", "com.unity.ai.inference", "3.0.0", "com.unity.ai.inference@2.4.0")]
        [TestCase("6000.0.23f1", "com.unity.ai.inference", "2.1.9", "com.unity.ai.inference@2.4.0")]
        // Outside the asmdef's versionDefines range (a pre-release sorts below its release: UnityCsReference SemVersion.cs).
        [TestCase("6000.0.23f1", "com.unity.ai.inference", "2.2.0-pre.1", "com.unity.ai.inference@2.4.0")]
        [TestCase("2022.3.11f1", "com.unity.sentis", "2.1.0-exp.2", "com.unity.sentis@2.1.3")]
        public void AnUnsupportedVersionIsReplaced(string unity, string name, string version, string expected)
        {
            var decision = InferencePackagePolicy.Decide(unity, Installed(name, version));
            Assert.That(decision.Action, Is.EqualTo(InferencePackageAction.Add));
            Assert.That(decision.PackageToAdd, Is.EqualTo(expected));
            StringAssert.Contains(version, decision.Message);
        }

        [TestCase("6000.5.2f1", "2.4.0")]
        [TestCase("6000.7.0a1", "2.3.0")]
        public void InstanceIdPackagesAreReplacedFrom6000_5(string unity, string installed)
        {
            var decision = InferencePackagePolicy.Decide(unity, Installed("com.unity.ai.inference", installed));
            Assert.That(decision.Action, Is.EqualTo(InferencePackageAction.Add));
            Assert.That(decision.PackageToAdd, Is.EqualTo("com.unity.ai.inference@2.2.2"));
            StringAssert.Contains("InstanceIDToObject(int)", decision.Message);
            StringAssert.Contains(installed, decision.Message);
        }

        [TestCase("")]
        [TestCase("unity")]
        [TestCase(".3.1f1")]
        public void AMalformedUnityVersionIsNamed(string unity)
        {
            var error = Assert.Throws<LpnnException>(() => InferencePackagePolicy.Decide(unity, Installed()));
            StringAssert.Contains("'" + unity + "'", error.Message);
        }
    }
}
