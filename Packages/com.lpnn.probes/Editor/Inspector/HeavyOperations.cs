using System.Collections.Generic;
using Lpnn.Probes.Core.Placement;
using Lpnn.Probes.Core.Selection;

namespace Lpnn.Probes.Editor
{
    /// <summary>Which <see cref="HeavyOperation"/>s a button of the volume's inspector starts, for
    /// <see cref="HeavyOperationPolicy"/>'s estimate (the rule itself lives in Core).</summary>
    internal static class HeavyOperations
    {
        /// <summary>Apply, or Find probes (<paramref name="searchOnly"/>: the search without the refinement); no insertion rounds
        /// when the whole ranking is known (<paramref name="rankingKnown"/>); the refinement avoids leaks as the volume does.</summary>
        public static List<HeavyOperation> Placement(LpnnVolume volume, SelectionPolicy policy, bool searchOnly, bool rankingKnown = false) =>
            HeavyOperationPolicy.PlacementOperations(volume.Method, policy == SelectionPolicy.Tolerance, searchOnly, volume.AvoidLightLeaks,
                RankingUsed(volume, rankingKnown));

        /// <summary>The placement panel's line of Apply's expected time (the text is Core's <see cref="HeavyOperationPolicy.ApplyLine"/>,
        /// priced leak-aware when the volume avoids light leaks); <paramref name="previewKnown"/>: Apply writes the preview as it is.</summary>
        public static string ApplyLine(LpnnVolume volume, SelectionPolicy policy, long points, bool rankingKnown, bool previewKnown) =>
            HeavyOperationPolicy.ApplyLine(points, volume.Method, policy, RankingUsed(volume, rankingKnown), previewKnown, volume.AvoidLightLeaks);

        /// <summary>A known ranking spares Apply the rounds (with pinned probes kept, the known ranking is the pinned order's:
        /// PlacementPanel asks PlacementInputs with the pins).</summary>
        private static bool RankingUsed(LpnnVolume volume, bool rankingKnown) => rankingKnown;

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
