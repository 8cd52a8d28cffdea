using System.Collections.Generic;
using System.Text;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.InUse;
using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Editor
{
    /// <summary>A text key of everything the grid depends on (world boxes and cell size, and the in-use rule with its
    /// settings): when it changes, the grid, lighting and features of a session no longer match the volume.</summary>
    internal static class GridSignature
    {
        public static string Of(IReadOnlyList<GridBox> worldBoxes, double cellSize)
        {
            var text = new StringBuilder(InvariantFormat.Number(cellSize));
            foreach (var box in worldBoxes) text.Append('|').Append(box.Center).Append(box.U).Append(box.V).Append(box.W);
            return text.ToString();
        }

        public static string Of(LpnnVolume volume) => Of(volume.GetWorldBoxes(), volume.CellSize) + InUseSettings(volume);

        /// <summary>The rule, its parameters, the floor source option and, when the rule reads them (Reachable; All's report),
        /// the seeds' world positions (a moved seed changes the walk). An empty seed entry is written as such, not refused:
        /// the Grid step names it. A rebaked NavMesh is not seen: build the grid again after baking.</summary>
        private static string InUseSettings(LpnnVolume volume)
        {
            var text = new StringBuilder("|in use ").Append((int)volume.InUseRule).Append(' ')
                .Append(InvariantFormat.Number(volume.InUseBandHeight)).Append(' ')
                .Append(InvariantFormat.Number(volume.InUseSlopeLimit)).Append(' ')
                .Append(InvariantFormat.Number(volume.InUseStepHeight)).Append(volume.UseNavMesh ? " navmesh" : " physics");
            if (volume.InUseRule == InUseRule.Band) return text.ToString();
            foreach (var seed in volume.InUseSeeds)
                text.Append(" seed ").Append(seed == null ? "empty" : InvariantFormat.Vector(seed.position.ToNumerics()));
            return text.ToString();
        }
    }
}
