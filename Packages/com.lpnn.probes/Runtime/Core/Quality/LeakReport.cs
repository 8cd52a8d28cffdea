using System;
using System.Collections.Generic;
using System.Threading;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.InUse;
using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Core.Quality
{
    /// <summary>The inspector's leak report of a placement (Documentation~/leaks.md "What is reported"): how many of the points
    /// in use leak (<see cref="LeakCheck"/>) and the tetrahedra that hold a leaking point, as 4 probe-list indices each, so the
    /// Scene view can draw them. Engine-free: the editor passes Unity's tetrahedralisation and physics rays.</summary>
    internal sealed class LeakReport
    {
        /// <summary>Leaking points among the points in use.</summary>
        public int Leaking { get; }
        /// <summary>Points in use (probes included: a probe never leaks).</summary>
        public int Points { get; }
        /// <summary>The tetrahedra holding at least one leaking point in use (or, outside the hull, owning its nearest hull
        /// triangle): 4 indices into the placement's probe list per tetrahedron, in the mesh's order, each once.</summary>
        public int[] LeakingTetrahedra { get; }

        public LeakReport(int leaking, int points, int[] leakingTetrahedra)
        {
            if (points < 0 || leaking < 0 || leaking > points)
                throw new ArgumentOutOfRangeException(nameof(leaking), leaking, "leaking points must be in 0.." + points);
            Leaking = leaking;
            Points = points;
            LeakingTetrahedra = leakingTetrahedra ?? new int[0];
        }

        /// <summary>Leaking share of the points in use, 0 when there are none.</summary>
        public double Fraction => Points == 0 ? 0.0 : (double)Leaking / Points;
        public int TetrahedronCount => LeakingTetrahedra.Length / 4;

        /// <summary>"12 of 3,456 points in use leak (0.35 %)".</summary>
        public string Describe() =>
            InvariantFormat.Count(Leaking) + " of " + InvariantFormat.Count(Points) + " points in use leak (" +
            InvariantFormat.Number(Math.Round(100.0 * Fraction, 2)) + " %)";

        /// <summary>"Leaks: 12 of 3,456 points in use leak (0.35 %), in 9 tetrahedra" — the line the inspector shows after Apply
        /// and batch mode logs (no final period: the inspector adds where the tetrahedra are drawn).
        /// <paramref name="countedNote"/> (e.g. " (every point counted: …)") follows the share when the points counted are
        /// not the points in use.</summary>
        public string Sentence(string countedNote = "") =>
            "Leaks: " + Describe() + (countedNote ?? "") + (TetrahedronCount > 0 ? ", in " + InvariantFormat.Count(TetrahedronCount) + (TetrahedronCount == 1 ? " tetrahedron" : " tetrahedra") : "");

        /// <summary>Which points of <paramref name="reference"/> leak under the placement, over the points in use only
        /// (<paramref name="inUse"/>: one flag per evaluation point; null: every point), with the tetrahedra holding them.</summary>
        /// <param name="probes">Evaluation point indices of the probes.</param>
        /// <param name="tetrahedra">4 indices into <paramref name="probes"/> per tetrahedron (Unity's tetrahedralisation).</param>
        public static LeakReport Compute(ReferenceLighting reference, int[] probes, int[] tetrahedra, bool[] inUse, IRaycaster raycaster,
            ProgressCallback progress, CancellationToken cancel)
        {
            if (reference == null) throw new ArgumentNullException(nameof(reference));
            if (inUse != null && inUse.Length != reference.Count)
                throw new ArgumentException("the in-use mask has " + inUse.Length + " flags for " + reference.Count + " points", nameof(inUse));
            ProbeIndices.Check(probes, reference.Count);
            var isProbe = new bool[reference.Count];
            foreach (int p in probes) isProbe[p] = true;
            var asked = new List<int>();
            int points = 0;
            for (int n = 0; n < reference.Count; n++)
            {
                if (inUse != null && !inUse[n]) continue;
                points++;
                if (!isProbe[n]) asked.Add(n);
            }
            var visited = new StencilLog(asked.Count);
            PlacementError.InterpolatePoints(reference, probes, tetrahedra, asked.ToArray(), null, visited.Visitor);
            if (visited.Count != asked.Count) throw new InvalidOperationException("a stencil per point asked for was expected");
            IReadOnlyList<Stencil> stencils = visited.Stencils;
            cancel.ThrowIfCancellationRequested();
            var leaks = LeakCheck.Leaking(reference, probes, visited.Points, stencils, raycaster, progress, cancel);
            var cells = new int[stencils.Count];
            for (int i = 0; i < cells.Length; i++) cells[i] = stencils[i].Cell;
            var mesh = TetrahedralMesh.Build(PlacementError.ProbePoints(reference, probes), tetrahedra);
            return new LeakReport(CountTrue(leaks, null), points, Vertices(mesh.Tetrahedra, CellsHolding(cells, leaks)));
        }

        /// <summary>The distinct cells (ascending) of the points that leak: <paramref name="cells"/> and
        /// <paramref name="leaking"/> are per point, in the same order.</summary>
        public static int[] CellsHolding(int[] cells, bool[] leaking)
        {
            if (cells.Length != leaking.Length)
                throw new ArgumentException("cells (" + cells.Length + ") and leak flags (" + leaking.Length + ") differ in length");
            var set = new SortedSet<int>();
            for (int i = 0; i < cells.Length; i++)
                if (leaking[i] && cells[i] >= 0) set.Add(cells[i]);
            var result = new int[set.Count];
            set.CopyTo(result);
            return result;
        }

        /// <summary>The 4 vertices of each of <paramref name="cells"/> in <paramref name="tetrahedra"/> (4 per tetrahedron).</summary>
        public static int[] Vertices(int[] tetrahedra, int[] cells)
        {
            var vertices = new int[4 * cells.Length];
            for (int c = 0; c < cells.Length; c++)
            {
                if ((uint)cells[c] >= (uint)(tetrahedra.Length / 4))
                    throw new ArgumentOutOfRangeException(nameof(cells), cells[c], "cell must be in 0.." + (tetrahedra.Length / 4 - 1));
                Array.Copy(tetrahedra, 4 * cells[c], vertices, 4 * c, 4);
            }
            return vertices;
        }

        /// <summary>How many flags are set, over the points of <paramref name="mask"/> only (null: all).</summary>
        public static int CountTrue(bool[] flags, bool[] mask)
        {
            if (mask != null && mask.Length != flags.Length)
                throw new ArgumentException("the mask has " + mask.Length + " flags for " + flags.Length + " points", nameof(mask));
            int count = 0;
            for (int i = 0; i < flags.Length; i++)
                if (flags[i] && (mask == null || mask[i])) count++;
            return count;
        }
    }
}
