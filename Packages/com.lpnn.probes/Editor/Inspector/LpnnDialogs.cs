using Lpnn.Probes.Core.Numerics;
using UnityEditor;

namespace Lpnn.Probes.Editor
{
    /// <summary>The inspector's confirmations before work that takes long or rewrites the scene's lighting
    /// (EditorUtility.DisplayDialog: UnityCsReference Editor/Mono/EditorUtility.bindings.cs).</summary>
    internal static class LpnnDialogs
    {
        /// <summary>True at once for grids up to <see cref="PointCountEstimate.LargeGrid"/> points; above, asks.</summary>
        public static bool ConfirmHeavy(long points, string what)
        {
            if (points <= PointCountEstimate.LargeGrid) return true;
            return EditorUtility.DisplayDialog(LpnnVolumeStyles.LargeGridTitle,
                "The grid has " + InvariantFormat.Count(points) + " points (about " + PointCountEstimate.CostOf(points) + "). Do you want to " + what +
                " now? You can cancel from the progress bar.", LpnnVolumeStyles.Continue, LpnnVolumeStyles.Cancel);
        }

        public static bool ConfirmSceneBake() =>
            EditorUtility.DisplayDialog(LpnnVolumeStyles.SceneBakeTitle, LpnnVolumeStyles.SceneBakeMessage, LpnnVolumeStyles.Bake, LpnnVolumeStyles.Cancel);
    }
}
