using System.Linq;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Json;
using Lpnn.Probes.Core.Quality;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests.Support
{
    /// <summary>The grid and dense lighting of a golden case written by Tools~/golden/make_*_golden.py: lattice ids at a
    /// cell size, their float32 positions (checked to be the grid's, exactly), float32 SH and the lighting scale.</summary>
    public static class GoldenLighting
    {
        public static EvaluationGrid Grid(JsonValue c)
        {
            var ids = c.Get("ids").Items.Select(row => new LatticeId((int)row.Items[0].AsNumber, (int)row.Items[1].AsNumber, (int)row.Items[2].AsNumber)).ToList();
            var grid = EvaluationGrid.FromIds(c.Get("cell_size").AsNumber, ids);
            var positions = c.Get("positions").Items;
            for (int n = 0; n < grid.Count; n++)
            {
                var p = grid.GetPosition(n);
                Assert.That(new[] { p.X, p.Y, p.Z }, Is.EqualTo(JsonArrays.Floats(positions[n])), "grid position of point " + n);
            }
            return grid;
        }

        public static ReferenceLighting Reference(JsonValue c, EvaluationGrid grid) =>
            ReferenceLighting.FromGrid(grid, c.Get("sh").Items.SelectMany(JsonArrays.Floats).ToArray(), c.Get("lighting_scale").AsNumber);
    }
}
