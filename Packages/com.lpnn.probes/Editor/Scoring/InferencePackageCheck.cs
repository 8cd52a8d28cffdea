using System.Collections.Generic;
using Lpnn.Probes.Core.Scoring;
using UnityEditor;
using UnityEditor.PackageManager;
using UnityEditor.PackageManager.Requests;
using UnityEngine;

namespace Lpnn.Probes.Editor
{
    /// <summary>Makes sure the project has exactly one .onnx importer (the rule and its sources:
    /// <see cref="InferencePackagePolicy"/>). The package declares no inference dependency, so after "Add package from git
    /// URL" this check lists the project's packages once per editor session and, when the policy says so, asks once to add
    /// the package of this Unity version or to remove Sentis beside Inference Engine; the volume inspector shows the same
    /// decision with a button. Package Manager calls: UnityCsReference 2022.3 / 6000.5
    /// Modules/PackageManager/Editor/Managed/Client.cs (List(bool, bool), Add(string), Remove(string)) and
    /// Requests/Request.cs (IsCompleted, Status, Error).</summary>
    [InitializeOnLoad]
    internal static class InferencePackageCheck
    {
        private const string AskedKey = "Lpnn.Probes.InferencePackageCheck.Asked";
        private static ListRequest _list;
        private static Request _change;

        /// <summary>The last decision (null until the package list arrived).</summary>
        public static InferencePackageDecision Current { get; private set; }

        /// <summary>True while a Package Manager request of this check runs.</summary>
        public static bool Busy => _list != null || _change != null;

        static InferencePackageCheck()
        {
            Refresh();
        }

        /// <summary>Lists the installed packages (offline: the project's manifest and lock, no registry query) and decides.</summary>
        public static void Refresh()
        {
            if (_list != null) return;
            _list = Client.List(true, true);
            EditorApplication.update += PollList;
        }

        /// <summary>Runs the Package Manager call of the current decision (Add or Remove); the domain reload that follows runs
        /// this check again.</summary>
        public static void Apply()
        {
            var decision = Current;
            if (decision == null || Busy) return;
            if (decision.Action == InferencePackageAction.Add) _change = Client.Add(decision.PackageToAdd);
            else if (decision.Action == InferencePackageAction.RemoveSentis) _change = Client.Remove(decision.Package);
            else return;
            Debug.Log("[LPNN] " + (decision.Action == InferencePackageAction.Add ? "adding " : "removing ") + decision.Package +
                      " through the Package Manager: " + decision.Message);
            EditorApplication.update += PollChange;
        }

        /// <summary>The dialog button that applies the decision.</summary>
        public static string ApplyLabel(InferencePackageDecision decision)
        {
            return decision.Action == InferencePackageAction.RemoveSentis ? "Remove " + decision.Package : "Install " + decision.PackageToAdd;
        }

        private static void PollList()
        {
            if (!_list.IsCompleted) return;
            EditorApplication.update -= PollList;
            var request = _list;
            _list = null;
            if (request.Status != StatusCode.Success)
            {
                Debug.LogWarning("[LPNN] could not list the project's packages to check the inference package: " +
                                 (request.Error != null ? request.Error.message : "unknown error") + ". " + LpnnScoring.PackageHint);
                return;
            }
            var installed = new Dictionary<string, string>();
            bool sentisIsDirect = true;
            foreach (var package in request.Result)
            {
                installed[package.name] = package.version;
                if (package.name == InferencePackagePolicy.SentisName) sentisIsDirect = package.isDirectDependency;
            }
            Current = InferencePackagePolicy.Decide(Application.unityVersion, installed, sentisIsDirect);
            if (Current.Action != InferencePackageAction.Ready) Offer(Current);
        }

        /// <summary>Asks once per editor session (SessionState survives domain reloads, not restarts); in batch mode, where
        /// no dialog can be answered, or when no Package Manager call can fix it (an indirect Sentis), it only logs what to do.</summary>
        private static void Offer(InferencePackageDecision decision)
        {
            if (Application.isBatchMode || decision.Action == InferencePackageAction.ResolveByHand)
            {
                Debug.LogWarning("[LPNN] " + decision.Message + " (LPNN Probes cannot score until then.)");
                return;
            }
            if (SessionState.GetBool(AskedKey, false)) return;
            SessionState.SetBool(AskedKey, true);
            if (EditorUtility.DisplayDialog("LPNN Probes: inference package", decision.Message, ApplyLabel(decision), "Not now"))
                Apply();
        }

        private static void PollChange()
        {
            if (!_change.IsCompleted) return;
            EditorApplication.update -= PollChange;
            var request = _change;
            _change = null;
            if (request.Status != StatusCode.Success)
                Debug.LogError("[LPNN] the Package Manager refused the change: " +
                               (request.Error != null ? request.Error.message : "unknown error") + ". " + LpnnScoring.PackageHint);
            Refresh();
        }
    }
}
