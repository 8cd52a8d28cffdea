using System;
using System.Collections.Generic;
using System.Globalization;

namespace Lpnn.Probes.Core.Scoring
{
    /// <summary>What the editor should do about the neural-network inference package of a project.</summary>
    internal enum InferencePackageAction
    {
        /// <summary>Exactly one supported package is installed: nothing to do.</summary>
        Ready = 0,
        /// <summary>No usable package: add <see cref="InferencePackageDecision.PackageToAdd"/>.</summary>
        Add = 1,
        /// <summary>Both packages are installed, so both register an .onnx importer and Unity rejects both: remove Sentis.</summary>
        RemoveSentis = 2,
        /// <summary>Both packages are installed but Sentis only as another package's dependency: Client.Remove cannot
        /// remove it, so the user must remove or upgrade that package (the message says so).</summary>
        ResolveByHand = 3,
    }

    /// <summary>The outcome of <see cref="InferencePackagePolicy.Decide"/>: the action, the package identifier for
    /// the Package Manager's <c>Client.Add</c> (or the name for <c>Client.Remove</c>) and a sentence for the user.</summary>
    internal sealed class InferencePackageDecision
    {
        public InferencePackageAction Action { get; }
        /// <summary>"name@version" for Add, the package name for RemoveSentis, empty for Ready.</summary>
        public string Package { get; }
        public string Message { get; }

        public InferencePackageDecision(InferencePackageAction action, string package, string message)
        {
            Action = action;
            Package = package ?? "";
            Message = message ?? "";
        }

        public string PackageToAdd => Action == InferencePackageAction.Add ? Package : "";
    }

    /// <summary>Which inference package a project needs, so that it has exactly one <c>.onnx</c> importer.
    ///
    /// com.unity.sentis 2.1.3 and com.unity.ai.inference 2.2+ both declare <c>[ScriptedImporter(..., new[] {"onnx"})]</c>
    /// (needle-mirror/com.unity.sentis 2.1.3 and needle-mirror/com.unity.ai.inference 2.4.0, Editor/ONNX/ONNXModelImporter.cs).
    /// When two scripted importers claim one extension Unity rejects all of them (UnityCsReference 2022.3 and 6000.5,
    /// Modules/AssetPipelineEditor/Public/ScriptedImporter.cs: "Multiple scripted importers are targeting the extension"),
    /// so the package cannot depend on either: Sentis is the only one for Unity 2022.3 (com.unity.ai.inference declares
    /// "unity": "6000.0"), and a Unity 6 project that already uses com.unity.ai.inference would get two importers. The
    /// editor instead asks this policy and offers the Package Manager call it returns.</summary>
    internal static class InferencePackagePolicy
    {
        public const string SentisName = "com.unity.sentis";
        public const string InferenceEngineName = "com.unity.ai.inference";
        /// <summary>The Sentis the Unity layer is compiled against (Unity 2022.3; needle-mirror/com.unity.sentis 2.1.3).</summary>
        public const string SentisVersion = "2.1.3";
        /// <summary>The com.unity.ai.inference installed on Unity 6000.0–6000.4: the newest the Unity layer is compiled against.</summary>
        public const string InferenceEngineVersion = "2.4.0";
        /// <summary>The com.unity.ai.inference installed on Unity 6000.5 and later. 2.3.0 and 2.4.0 call
        /// <c>EditorUtility.InstanceIDToObject(int)</c> (needle-mirror/com.unity.ai.inference 2.4.0,
        /// Editor/Visualizer/Editor/ModelAssetOpenHandler.cs:13), which UnityCsReference 6000.5, 6000.6 and 6000.7 mark
        /// <c>[Obsolete(..., true)]</c> (Editor/Mono/EditorUtility.bindings.cs:60; only a warning up to 6000.4), so the
        /// package does not compile there and Unity stops loading new assemblies. 2.2.2 is the newest release whose sources
        /// use no member obsolete as an error in 6000.5 or 6000.7 (Tools~/UnityApiSurface/Generated/obsolete-error-uses.txt,
        /// checked by InferencePackageCompatibilityTests).</summary>
        public const string InferenceEngineVersionForEntityIdUnity = "2.2.2";
        /// <summary>The first Unity 6000 minor version where InstanceIDToObject(int) is an error (see above).</summary>
        public const int EntityIdOnlyFirstMinor = 5;
        /// <summary>The first Unity major version of com.unity.ai.inference (its package.json: "unity": "6000.0").</summary>
        public const int InferenceEngineFirstUnityMajor = 6000;

        /// <summary>Decides from the editor's version (Application.unityVersion, e.g. "2022.3.11f1" or "6000.0.23f1") and the
        /// installed packages (name → version, e.g. from Client.List). <paramref name="sentisIsDirect"/>: whether Sentis is
        /// in the project manifest (PackageInfo.isDirectDependency, UnityCsReference
        /// Modules/PackageManager/Editor/Managed/PackageInfo.cs); Client.Remove removes only direct dependencies.</summary>
        public static InferencePackageDecision Decide(string unityVersion, IReadOnlyDictionary<string, string> installed, bool sentisIsDirect = true)
        {
            if (installed == null) throw new ArgumentNullException(nameof(installed));
            int unityMajor = UnityMajor(unityVersion);
            installed.TryGetValue(SentisName, out string sentis);
            installed.TryGetValue(InferenceEngineName, out string engine);
            bool entityIdOnly = IsEntityIdOnly(unityVersion);
            string engineVersion = entityIdOnly ? InferenceEngineVersionForEntityIdUnity : InferenceEngineVersion;
            string engineRange = entityIdOnly ? "[2.2, 2.3)" : "[2.2, 3.0)";
            string recommended = unityMajor >= InferenceEngineFirstUnityMajor
                ? InferenceEngineName + "@" + engineVersion
                : SentisName + "@" + SentisVersion;

            if (sentis != null && engine != null && !sentisIsDirect)
                return new InferencePackageDecision(InferencePackageAction.ResolveByHand, "",
                    "Both " + SentisName + " " + sentis + " and " + InferenceEngineName + " " + engine + " are installed, so Unity rejects " +
                    "both .onnx importers, but " + SentisName + " comes in as a dependency of another package and cannot be removed " +
                    "on its own. Remove or upgrade the package that depends on it (Window > Package Manager shows which).");
            if (sentis != null && engine != null)
                return new InferencePackageDecision(InferencePackageAction.RemoveSentis, SentisName,
                    "Both " + SentisName + " " + sentis + " and " + InferenceEngineName + " " + engine + " are installed. Each registers an " +
                    ".onnx importer, so Unity rejects both and no model can be imported. Remove " + SentisName + " (Inference Engine " +
                    "replaces it).");
            if (engine != null)
            {
                if (InRange(engine, 2, 2) && !(entityIdOnly && !InRange(engine, 2, 2, 2)))
                    return Ready(InferenceEngineName, engine);
                string reason = entityIdOnly && InRange(engine, 2, 2)
                    ? " on Unity " + unityVersion + ": 2.3.0 and 2.4.0 call EditorUtility.InstanceIDToObject(int), a compile error " +
                      "from Unity 6000.5 on, which stops Unity loading new assemblies"
                    : "";
                return new InferencePackageDecision(InferencePackageAction.Add, InferenceEngineName + "@" + engineVersion,
                    InferenceEngineName + " " + engine + " is outside the supported range " + engineRange + reason + ". Install " +
                    engineVersion + ".");
            }
            if (sentis != null)
            {
                if (InRange(sentis, 2, 1)) return Ready(SentisName, sentis);
                return new InferencePackageDecision(InferencePackageAction.Add, recommended,
                    SentisName + " " + sentis + " is outside the supported range [2.1, 3.0). Install " + recommended + ".");
            }
            return new InferencePackageDecision(InferencePackageAction.Add, recommended,
                "No neural-network inference package is installed, so the model cannot be imported or run. Install " + recommended + ".");
        }

        private static InferencePackageDecision Ready(string name, string version)
        {
            return new InferencePackageDecision(InferencePackageAction.Ready, "", name + " " + version + " runs the model.");
        }

        /// <summary>Major version of a Unity version string ("2022.3.11f1" → 2022); throws with the value when it is not one.</summary>
        public static int UnityMajor(string unityVersion)
        {
            string text = unityVersion ?? "";
            int dot = text.IndexOf('.');
            if (dot <= 0 || !int.TryParse(text.Substring(0, dot), NumberStyles.None, CultureInfo.InvariantCulture, out int major))
                throw new LpnnException("'" + text + "' is not a Unity version (expected e.g. 2022.3.11f1)");
            return major;
        }

        /// <summary>True for Unity 6000.5 and later (and any later major), where InstanceIDToObject(int) is an error.</summary>
        public static bool IsEntityIdOnly(string unityVersion)
        {
            int major = UnityMajor(unityVersion);
            if (major != InferenceEngineFirstUnityMajor) return major > InferenceEngineFirstUnityMajor;
            string text = unityVersion.Substring(unityVersion.IndexOf('.') + 1);
            int end = 0;
            while (end < text.Length && char.IsDigit(text[end])) end++;
            if (end == 0 || !int.TryParse(text.Substring(0, end), NumberStyles.None, CultureInfo.InvariantCulture, out int minor))
                throw new LpnnException("'" + unityVersion + "' is not a Unity version (expected e.g. 6000.5.2f1)");
            return minor >= EntityIdOnlyFirstMinor;
        }

        /// <summary>True for versions in [major.minMinor, major.maxMinor] (any patch, pre-releases included).</summary>
        private static bool InRange(string version, int major, int minMinor, int maxMinor)
        {
            return InRange(version, major, minMinor) && int.Parse(version.Split('.')[1], CultureInfo.InvariantCulture) <= maxMinor;
        }

        /// <summary>True for versions in [major.minMinor.0, major+1.0.0), as the Editor asmdef's versionDefines ranges
        /// ("[2.2.0,3.0.0)", "[2.1.0,3.0.0)") decide whether LPNN_INFERENCE_ENGINE / LPNN_SENTIS is defined: a pre-release sorts
        /// below its release (UnityCsReference Editor/Mono/Scripting/ScriptCompilation/SemVersion.cs, CompareExtension with
        /// lower = true), so "2.2.0-pre.1" is outside [2.2.0, ...) while "2.2.1-pre.1" is inside.</summary>
        private static bool InRange(string version, int major, int minMinor)
        {
            int dash = version.IndexOf('-');
            string[] parts = (dash < 0 ? version : version.Substring(0, dash)).Split('.');
            if (parts.Length < 3) return false;
            if (!int.TryParse(parts[0], NumberStyles.None, CultureInfo.InvariantCulture, out int vMajor)) return false;
            if (!int.TryParse(parts[1], NumberStyles.None, CultureInfo.InvariantCulture, out int vMinor)) return false;
            if (!int.TryParse(parts[2], NumberStyles.None, CultureInfo.InvariantCulture, out int vPatch)) return false;
            bool preRelease = dash >= 0;
            if (vMajor != major || vMinor < minMinor) return false;
            return !(preRelease && vMinor == minMinor && vPatch == 0);
        }
    }
}
