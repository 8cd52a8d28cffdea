using System;
using System.Collections.Generic;
using System.Numerics;
using System.Threading;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Core.InUse
{
    /// <summary>Where the walk starts (Documentation~/in-use.md "Definitions" 3): a seed s attaches to every in-band point q
    /// with |q − s| ≤ 2h whose segment from s to q is free.</summary>
    internal static class SeedAttachment
    {
        public const double ReachCells = 2.0;

        /// <summary>The seeds as doubles; an error naming the first non-finite one, or when there is none.</summary>
        public static Double3[] Checked(Vector3[] seeds)
        {
            if (seeds == null)
                throw new InUseException("the 'reachable' rule needs seeds (none given): add seeds (spawn points, items, the volume's " +
                                         "seed transforms), or use the rule 'band'");
            if (seeds.Length == 0)
                throw new InUseException("the 'reachable' rule needs at least one seed (0 given): add seeds (spawn points, items, the " +
                                         "volume's seed transforms), or use the rule 'band'");
            var values = new Double3[seeds.Length];
            int bad = 0, first = -1;
            for (int s = 0; s < seeds.Length; s++)
            {
                values[s] = Double3.FromVector3(seeds[s]);
                if (values[s].IsFinite) continue;
                if (first < 0) first = s;
                bad++;
            }
            if (bad > 0)
                throw new InUseException("seed " + first + " is " + InvariantFormat.Vector(seeds[first]) + ", not finite (" + bad + " of " +
                                         seeds.Length + " seeds are not): give every seed a finite position");
            return values;
        }

        /// <summary>Indices of the in-band points some seed attaches to, ascending.</summary>
        public static int[] Starts(EvaluationGrid grid, IRaycaster raycaster, bool[] inBand, Double3[] seeds,
            ProgressCallback progress, CancellationToken cancel)
        {
            double h = grid.CellSize, reach = ReachCells * h;
            // Candidates: the lattice box around each seed, one id wider than 2h on each side (the exact test follows).
            int span = (int)(2 * ReachCells) + 4;
            var origins = new List<Double3>();
            var targets = new List<Double3>();
            var points = new List<int>();
            foreach (var seed in seeds)
            {
                double lowX = Math.Floor((seed.X - reach) / h) - 1, lowY = Math.Floor((seed.Y - reach) / h) - 1,
                    lowZ = Math.Floor((seed.Z - reach) / h) - 1;
                if (!WithinLattice(lowX, span) || !WithinLattice(lowY, span) || !WithinLattice(lowZ, span)) continue; // attaches to nothing
                for (int k = 0; k < span; k++)
                for (int j = 0; j < span; j++)
                for (int i = 0; i < span; i++)
                {
                    int point = grid.IndexOf(new LatticeId((int)lowX + i, (int)lowY + j, (int)lowZ + k));
                    if (point < 0 || !inBand[point]) continue;
                    var position = Double3.FromVector3(grid.GetPosition(point));
                    if (!((position - seed).Length <= reach)) continue;
                    origins.Add(seed);
                    targets.Add(position);
                    points.Add(point);
                }
            }
            var free = InUseRays.SegmentsFree(origins.ToArray(), targets.ToArray(), raycaster, "in use: seed attachment rays", progress, cancel);
            var starts = new SortedSet<int>();
            for (int c = 0; c < points.Count; c++) if (free[c]) starts.Add(points[c]);
            var result = new int[starts.Count];
            starts.CopyTo(result);
            return result;
        }

        private static bool WithinLattice(double low, int span) =>
            low >= -LatticeId.MaxCoordinate && low + span <= LatticeId.MaxCoordinate;
    }
}
