using System;
using System.Collections.Generic;
using System.Numerics;
using System.Threading;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Core.InUse
{
    /// <summary>The in-use rule of Documentation~/in-use.md: which evaluation points dynamic objects go to. Python's
    /// lpnn.core.in_use implements the same text; Tests/Data/in_use_golden.json pins both to the same masks.</summary>
    internal static class InUseMask
    {
        /// <summary>One flag per grid point: in use by <paramref name="rule"/>. An error when no point is, when the
        /// reachable rule has no seed, or when its seeds attach to no in-band point. <paramref name="seeds"/> (metres) are
        /// read by <see cref="InUseRule.Reachable"/> only. Progress per batch of rays; cancel between batches.</summary>
        public static bool[] Compute(EvaluationGrid grid, IRaycaster raycaster, InUseParameters parameters, InUseRule rule,
            Vector3[] seeds, ProgressCallback progress, CancellationToken cancel = default) =>
            Compute(grid, raycaster, raycaster, parameters, rule, seeds, progress, cancel);

        /// <summary>As above, with the floor rays (definitions 1 and 4's floor profile) cast through
        /// <paramref name="floorRaycaster"/> and the segment rays (definitions 2–4) through <paramref name="segmentRaycaster"/>:
        /// e.g. floors from a navigation mesh, walls from the scene's colliders (the Unity volume with a baked NavMesh).</summary>
        public static bool[] Compute(EvaluationGrid grid, IRaycaster floorRaycaster, IRaycaster segmentRaycaster, InUseParameters parameters,
            InUseRule rule, Vector3[] seeds, ProgressCallback progress, CancellationToken cancel = default)
        {
            if (grid == null) throw new ArgumentNullException(nameof(grid));
            if (parameters == null) throw new ArgumentNullException(nameof(parameters));
            string name = InUseRules.Name(rule);
            if (rule == InUseRule.All)
            {
                var all = new bool[grid.Count];
                for (int p = 0; p < all.Length; p++) all[p] = true;
                return all;
            }
            var mask = rule == InUseRule.Band
                ? Band(grid, floorRaycaster, parameters, progress, cancel).InBand
                : Reachable(grid, floorRaycaster, segmentRaycaster, parameters, seeds, null, progress, cancel);
            if (Array.IndexOf(mask, true) < 0) throw NoPointInUse(name, grid, parameters);
            return mask;
        }

        /// <summary>Definitions 1: each point's floor ray; in band when it hits a walkable surface within H.</summary>
        public static InUseBand Band(EvaluationGrid grid, IRaycaster raycaster, InUseParameters parameters, ProgressCallback progress,
            CancellationToken cancel = default)
        {
            if (grid == null) throw new ArgumentNullException(nameof(grid));
            var positions = new Double3[grid.Count];
            for (int p = 0; p < positions.Length; p++) positions[p] = Double3.FromVector3(grid.GetPosition(p));
            var floor = InUseRays.FloorHeights(positions, raycaster, parameters, "in use: floor rays", progress, cancel);
            var inBand = new bool[grid.Count];
            for (int p = 0; p < inBand.Length; p++) inBand[p] = !double.IsNaN(floor[p]);
            return new InUseBand(inBand, floor);
        }

        /// <summary>Definitions 3–5: the in-band points the moves reach from the seeds' start points. <paramref name="band"/>:
        /// what <see cref="Band"/> returned, or null to cast the floor rays here.</summary>
        public static bool[] Reachable(EvaluationGrid grid, IRaycaster raycaster, InUseParameters parameters, Vector3[] seeds,
            InUseBand band, ProgressCallback progress, CancellationToken cancel = default) =>
            Reachable(grid, raycaster, raycaster, parameters, seeds, band, progress, cancel);

        /// <summary>As above, floor rays through <paramref name="floorRaycaster"/>, segment rays through
        /// <paramref name="segmentRaycaster"/>.</summary>
        public static bool[] Reachable(EvaluationGrid grid, IRaycaster floorRaycaster, IRaycaster segmentRaycaster, InUseParameters parameters,
            Vector3[] seeds, InUseBand band, ProgressCallback progress, CancellationToken cancel = default)
        {
            if (grid == null) throw new ArgumentNullException(nameof(grid));
            if (parameters == null) throw new ArgumentNullException(nameof(parameters));
            var checkedSeeds = SeedAttachment.Checked(seeds);
            band = band ?? Band(grid, floorRaycaster, parameters, progress, cancel);
            if (band.InBand.Length != grid.Count || band.FloorHeights.Length != grid.Count)
                throw new InUseException("the band has " + band.InBand.Length + " entries for a grid of " + InvariantFormat.Count(grid.Count) +
                                         " points: pass what Band returned for this grid");
            int inBand = band.Count;
            if (inBand == 0) throw NoPointInUse(InUseRules.Name(InUseRule.Reachable), grid, parameters);
            var starts = SeedAttachment.Starts(grid, segmentRaycaster, band.InBand, checkedSeeds, progress, cancel);
            if (starts.Length == 0)
                throw new InUseException(
                    "none of the " + InvariantFormat.Count(checkedSeeds.Length) + " seeds attaches to an in-band point (one within " +
                    InvariantFormat.Number(SeedAttachment.ReachCells * grid.CellSize) + " m, 2 cells, with nothing in between; " +
                    InvariantFormat.Count(inBand) + " of " + InvariantFormat.Count(grid.Count) + " points are in band): move the seeds " +
                    "into the volume near walkable floors, add seeds, or use the rule 'band'");
            var sources = new List<int>();
            var targets = new List<int>();
            InUseMoves.Collect(grid, floorRaycaster, segmentRaycaster, parameters, band, sources, targets, progress, cancel);
            return ReachableWalk.Reach(grid.Count, starts, sources, targets);
        }

        private static InUseException NoPointInUse(string rule, EvaluationGrid grid, InUseParameters parameters) =>
            new InUseException("the in-use rule '" + rule + "' leaves no point in use among the grid's " + InvariantFormat.Count(grid.Count) +
                               " points (band height " + InvariantFormat.Number(parameters.BandHeight) + " m, cell size " +
                               InvariantFormat.Number(grid.CellSize) + " m): no point lies within the band height above a walkable " +
                               "floor; use the rule 'all', or a band height larger than the cell size and the points' height above the floor");
    }
}
