using System.Collections.Generic;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Placement;
using UnityEditor;

namespace Lpnn.Probes.Editor
{
    /// <summary>The inspector's confirmations before work that takes long or rewrites the scene's lighting
    /// (EditorUtility.DisplayDialog: UnityCsReference Editor/Mono/EditorUtility.bindings.cs).</summary>
    internal static class LpnnDialogs
    {
        /// <summary>True at once when <see cref="HeavyOperationPolicy"/> expects the work to be short; otherwise shows the
        /// estimate and asks. The caller must end the GUI pass after a dialog (InspectorLayout.EndGuiAfterModal).</summary>
        public static bool ConfirmHeavy(long points, string what, params HeavyOperation[] operations) =>
            ConfirmHeavy(points, what, (IEnumerable<HeavyOperation>)operations);

        public static bool ConfirmHeavy(long points, string what, IEnumerable<HeavyOperation> operations)
        {
            var estimate = HeavyOperationPolicy.Estimate(points, operations);
            if (!estimate.NeedsConfirmation) return true;
            string time = estimate.Describe();
            return EditorUtility.DisplayDialog(LpnnVolumeStyles.LargeGridTitle,
                "The grid has " + InvariantFormat.Count(points) + " points (about " + PointCountEstimate.CostOf(points) + " of memory" +
                (time.Length > 0 ? "; " + time : "") + "). Do you want to " + what + " now? You can cancel from the progress bar.",
                LpnnVolumeStyles.Continue, LpnnVolumeStyles.Cancel);
        }

        public static bool ConfirmSceneBake() =>
            EditorUtility.DisplayDialog(LpnnVolumeStyles.SceneBakeTitle, LpnnVolumeStyles.SceneBakeMessage, LpnnVolumeStyles.Bake, LpnnVolumeStyles.Cancel);
    }
}
