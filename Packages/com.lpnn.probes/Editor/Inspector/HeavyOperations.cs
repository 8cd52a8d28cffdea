using System.Collections.Generic;
using Lpnn.Probes.Core.Placement;
using Lpnn.Probes.Core.Selection;

namespace Lpnn.Probes.Editor
{
    /// <summary>Which <see cref="HeavyOperation"/>s a button of the volume's inspector starts, for
    /// <see cref="HeavyOperationPolicy"/>'s estimate (the rule itself lives in Core).</summary>
    internal static class HeavyOperations
    {
        /// <summary>Apply, or Find probes (<paramref name="searchOnly"/>: the search without the refinement).</summary>
        public static List<HeavyOperation> Placement(LpnnVolume volume, SelectionPolicy policy, bool searchOnly) =>
            HeavyOperationPolicy.PlacementOperations(PlacementMethods.RanksByInsertion(volume.Method), policy == SelectionPolicy.Tolerance,
                volume.RefineInBatches, searchOnly);

        /// <summary>Run all: every step the volume's method needs, then its placement.</summary>
        public static List<HeavyOperation> RunAll(LpnnVolume volume)
        {
            var policy = volume.GetSelectionSettings().Policy;
            var operations = new List<HeavyOperation> { HeavyOperation.Grid, HeavyOperation.Lighting, HeavyOperation.Features };
            if (PlacementMethods.NeedsScores(volume.Method)) operations.Add(HeavyOperation.Scoring);
            operations.AddRange(Placement(volume, policy, false));
            return operations;
        }
    }
}
