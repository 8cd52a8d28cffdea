using System.Collections.Generic;
using System.Text;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Editor
{
    /// <summary>A text key of everything the grid depends on (world boxes and cell size): when it changes, the grid,
    /// lighting and features of a session no longer match the volume.</summary>
    internal static class GridSignature
    {
        public static string Of(IReadOnlyList<GridBox> worldBoxes, double cellSize)
        {
            var text = new StringBuilder(InvariantFormat.Number(cellSize));
            foreach (var box in worldBoxes) text.Append('|').Append(box.Center).Append(box.U).Append(box.V).Append(box.W);
            return text.ToString();
        }

        public static string Of(LpnnVolume volume) => Of(volume.GetWorldBoxes(), volume.CellSize);
    }
}
