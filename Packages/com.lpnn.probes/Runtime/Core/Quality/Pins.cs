using System;
using System.Collections.Generic;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Selection;

namespace Lpnn.Probes.Core.Quality
{
    /// <summary>Pinned probes a placement cannot keep (Documentation~/pins.md); the message names the pin and what to do.</summary>
    internal sealed class PinException : LpnnException
    {
        public PinException(string message) : base(message) { }
    }

    /// <summary>Pinned probes (Documentation~/pins.md): the artist's probes every placement keeps. A pin is a world position;
    /// it stands for its nearest evaluation point (ties: the lower index), which must lie within <see cref="SnapRadiusCells"/>
    /// cells (half the cell diagonal), and no new probe comes closer than the minimum distance (default
    /// <see cref="MinDistanceCells"/> cell) to a pin. Port of lpnn/quality/placement/pins.py; Tests/Data/pins_golden.json pins both.</summary>
    internal sealed class Pins
    {
        /// <summary>Half the cell diagonal: the farthest a position inside a fully covered cell is from its nearest corner.</summary>
        public static readonly double SnapRadiusCells = Math.Sqrt(3.0) / 2.0;
        /// <summary>One cell: the grid samples the lighting every cell, so a new probe closer than that to a pin adds nothing the
        /// metric can tell apart from it (pins.md "Why").</summary>
        public const double MinDistanceCells = 1.0;
        /// <summary>Distances are compared with this slack (× the cell size): an on-grid pin's neighbours, one cell away give or
        /// take float32 rounding, stay candidates.</summary>
        public const double SlackCells = 1e-3;

        /// <summary>The artist's positions, in the given order (what Apply writes back).</summary>
        public Double3[] Positions { get; }
        /// <summary>The grid index each pin stands for, in the pins' order.</summary>
        public int[] Indices { get; }
        /// <summary>One flag per grid point: never a new probe (the pins' own points and those within the minimum distance).</summary>
        public bool[] Blocked { get; }
        public double MinDistance { get; }
        public int Count => Indices.Length;

        private Pins(Double3[] positions, int[] indices, bool[] blocked, double minDistance)
        {
            Positions = positions;
            Indices = indices;
            Blocked = blocked;
            MinDistance = minDistance;
        }

        /// <summary>Snaps <paramref name="positions"/> to the grid's points (only the valid ones when <paramref name="valid"/> is
        /// given: a point inside geometry is never a probe) and blocks the points within <paramref name="minDistance"/> (null:
        /// one cell) of a pin. Throws <see cref="PinException"/> naming the bad pin: none given, a non-finite position, two pins
        /// at one position, a pin farther than half a cell diagonal from every point, two pins standing for one point.</summary>
        public static Pins Snap(EvaluationGrid grid, IReadOnlyList<Double3> positions, double? minDistance = null, bool[] valid = null)
        {
            if (grid == null) throw new ArgumentNullException(nameof(grid));
            if (positions == null || positions.Count == 0)
                throw new PinException("no pinned positions were given: pin at least one probe, or leave the pins out");
            double h = grid.CellSize;
            var pins = new Double3[positions.Count];
            for (int p = 0; p < pins.Length; p++)
            {
                pins[p] = positions[p];
                if (!(IsFinite(pins[p].X) && IsFinite(pins[p].Y) && IsFinite(pins[p].Z)))
                    throw new PinException("pinned probe " + p + " is at " + Where(pins[p]) + ", not a finite position: fix or remove it");
            }
            double distance = minDistance ?? MinDistanceCells * h;
            if (!(IsFinite(distance) && distance >= 0.0))
                throw new PinException("pin minimum distance " + InvariantFormat.Number(distance) +
                                       " must be a distance >= 0 in the volume's units (default one cell, " + InvariantFormat.Number(MinDistanceCells * h) + ")");
            var seen = new Dictionary<Double3, int>();
            for (int p = 0; p < pins.Length; p++)
            {
                if (seen.TryGetValue(pins[p], out int first))
                    throw new PinException("pinned probes " + first + " and " + p + " are both at " + Where(pins[p]) + ": remove the duplicate");
                seen[pins[p]] = p;
            }
            int n = grid.Count;
            var points = new Double3[n];
            for (int i = 0; i < n; i++)
            {
                var v = grid.GetPosition(i);
                points[i] = new Double3(v.X, v.Y, v.Z);
            }
            double radius = (SnapRadiusCells + SlackCells) * h;
            var indices = new int[pins.Length];
            var taken = new Dictionary<int, int>();
            for (int p = 0; p < pins.Length; p++)
            {
                // Nearest, then every point as near to 1e-9 of a cell: the lowest index among them (pins.py does the same).
                double nearest = double.PositiveInfinity;
                for (int i = 0; i < n; i++)
                    if (valid == null || valid[i]) nearest = Math.Min(nearest, Distance(points[i], pins[p]));
                if (!(nearest <= radius))
                    throw new PinException("pinned probe " + p + " at " + Where(pins[p]) + " is " + InvariantFormat.Number(nearest) +
                                           " from the nearest evaluation point, more than half a cell diagonal (" + InvariantFormat.Number(SnapRadiusCells * h) +
                                           "): it is outside the volume's points (in use); move it inside or leave it out of the pins");
                int index = -1;
                for (int i = 0; i < n && index < 0; i++)
                    if ((valid == null || valid[i]) && Distance(points[i], pins[p]) <= nearest + 1e-9 * h) index = i;
                if (taken.TryGetValue(index, out int other))
                    throw new PinException("pinned probes " + other + " and " + p + " (" + Where(pins[other]) + ", " + Where(pins[p]) +
                                           ") both stand for evaluation point " + index + " at " + Where(points[index]) +
                                           ": keep one of them, or use a smaller cell size");
                taken[index] = p;
                indices[p] = index;
            }
            var blocked = new bool[n];
            foreach (int index in indices) blocked[index] = true;
            if (distance > 0.0)
            {
                double within = distance - SlackCells * h;
                for (int i = 0; i < n; i++)
                    for (int p = 0; p < pins.Length && !blocked[i]; p++)
                        if (Distance(points[i], pins[p]) < within) blocked[i] = true;
            }
            return new Pins(pins, indices, blocked, distance);
        }

        /// <summary>The message when a volume keeps pinned probes but places with a method that cannot (the Network method).</summary>
        public const string NeedsInsertionMethod =
            "Keep Pinned Probes works with the insertion methods: set Method to Insertion, refined (the default) or another insertion method (or turn the toggle off)";

        /// <summary>The pins a volume's Apply keeps (Documentation~/pins.md "Every method"): null when <paramref name="keep"/>
        /// is off (the positions are then ignored, even if some are stored); a <see cref="PinException"/> when
        /// <paramref name="method"/> is not an insertion method (the Network method's spread ranking has no start the pins
        /// could head); otherwise <see cref="Snap"/> with the default minimum distance. Apply, its preview and batch mode ask
        /// this one question, so they agree on which probes are kept.</summary>
        public static Pins KeptBy(PlacementMethod method, bool keep, IReadOnlyList<Double3> positions, EvaluationGrid grid, bool[] valid)
        {
            if (!keep) return null;
            if (!PlacementMethods.RanksByInsertion(method)) throw new PinException(NeedsInsertionMethod);
            return Snap(grid, positions, null, valid);
        }

        /// <summary>Whether <paramref name="ranking"/> (grid indices, most important first) is an order made with these pins:
        /// it starts with them, in their order, and ranks no other blocked point. A pin-free ranking fails this (its start is
        /// the typical tetrahedron), so a selection from it cannot pass for one that keeps the pins.</summary>
        public bool Heads(int[] ranking)
        {
            if (ranking == null || ranking.Length < Count) return false;
            for (int p = 0; p < Count; p++)
                if (ranking[p] != Indices[p]) return false;
            for (int r = Count; r < ranking.Length; r++)
                if ((uint)ranking[r] < (uint)Blocked.Length && Blocked[ranking[r]]) return false;
            return true;
        }

        /// <summary>These pins on a subset of the grid (<paramref name="rows"/>: the grid index of each point of the subset, e.g.
        /// the valid points), which must hold every pinned point (<see cref="Snap"/> with the subset's valid flags does).</summary>
        public Pins OfRows(int[] rows)
        {
            var rowOf = new Dictionary<int, int>(rows.Length);
            for (int m = 0; m < rows.Length; m++) rowOf[rows[m]] = m;
            var indices = new int[Indices.Length];
            for (int p = 0; p < indices.Length; p++)
                if (!rowOf.TryGetValue(Indices[p], out indices[p]))
                    throw new PinException("pinned probe " + p + " stands for evaluation point " + Indices[p] + ", which is not a candidate (inside geometry): " +
                                           "move the probe out of the geometry");
            var blocked = new bool[rows.Length];
            for (int m = 0; m < rows.Length; m++) blocked[m] = Blocked[rows[m]];
            return new Pins(Positions, indices, blocked, MinDistance);
        }

        /// <summary>A budget's probe count, which counts the pins: fewer than the pins is an error naming both numbers.</summary>
        public void CheckCount(int count)
        {
            if (count < Count)
                throw new PinException("the budget keeps " + InvariantFormat.Count(count) + " probes but " + InvariantFormat.Count(Count) +
                                       " are pinned: raise the budget to at least " + InvariantFormat.Count(Count) + " probes, or pin fewer");
        }

        /// <summary>Insertion's start with pins (pins.md): the pins, then the usual start's points that are not blocked, then —
        /// only if those lie in one plane — the first free points by index that make a tetrahedron. Indices of
        /// <paramref name="grid"/>; <paramref name="blocked"/> and <paramref name="pinned"/> index the same points.</summary>
        public static int[] Start(EvaluationGrid grid, int[] pinned, bool[] blocked, int[] usual)
        {
            int n = grid.Count;
            var preference = new List<int>(n);
            var listed = new bool[n];
            foreach (int p in pinned)
            {
                preference.Add(p);
                listed[p] = true;
            }
            foreach (int p in usual)
                if (!blocked[p] && !listed[p])
                {
                    preference.Add(p);
                    listed[p] = true;
                }
            var begun = new HashSet<int>(preference);
            for (int p = 0; p < n; p++)
                if (!listed[p] && !blocked[p]) preference.Add(p);
            for (int p = 0; p < n; p++)
                if (!listed[p] && blocked[p]) preference.Add(p);
            var order = preference.ToArray();
            var rankOf = new int[n];
            for (int r = 0; r < n; r++) rankOf[order[r]] = r;
            TetrahedronGuarantee.Ensure(grid, order, begun);
            var start = new int[begun.Count];
            begun.CopyTo(start);
            Array.Sort(start, (a, b) => rankOf[a].CompareTo(rankOf[b]));
            return start;
        }

        private static bool IsFinite(double value) => !double.IsNaN(value) && !double.IsInfinity(value);

        private static double Distance(Double3 a, Double3 b)
        {
            double dx = a.X - b.X, dy = a.Y - b.Y, dz = a.Z - b.Z;
            return Math.Sqrt(dx * dx + dy * dy + dz * dz);
        }

        private static string Where(Double3 v) => "(" + InvariantFormat.Number(v.X) + ", " + InvariantFormat.Number(v.Y) + ", " + InvariantFormat.Number(v.Z) + ")";
    }
}
