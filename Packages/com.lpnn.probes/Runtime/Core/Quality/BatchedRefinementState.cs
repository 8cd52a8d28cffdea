using System.Collections.Generic;
using System.Numerics;

namespace Lpnn.Probes.Core.Quality
{
    /// <summary>One probe set of <see cref="BatchedRefinement"/> evaluated (Documentation~/quality.md §5.3): per point its
    /// error, the probes its stencil weighs and every probe its stencil touches; the Delaunay graph; the error sum. A trial
    /// (<see cref="RemovalCosts"/>) is interpolated only at the points whose stencil weighs a candidate, and the set
    /// without some probes (<see cref="Without"/>) only at the points whose stencil touched one: the tie-broken Delaunay
    /// is unique, so every other tetrahedron survives a removal, and a point outside the shrinking hull keeps its nearest
    /// hull point unless that point's triangle had a removed vertex. Port of lpnn/quality/placement/batched_state.py, except that
    /// the set without some probes is tetrahedralised again (Unity's native tetrahedraliser) rather than derived.
    /// With a <see cref="LeakWeighting"/> every error the state holds, sums and compares is the weighted one, and trials and
    /// removals keep it, as the Python state does.</summary>
    internal sealed class BatchedRefinementState
    {
        internal int[] Probes;      // sorted evaluation point indices
        internal double[] Errors;   // per point, 0 at the probes
        internal int[] Owners;      // 4 per point: the probes (point indices) its stencil weighs > 0, else -1
        internal int[] Touched;     // 4 per point: every probe (point index) of its stencil, zero weights included; -1 at probes
        internal int[] EdgeStart;   // CSR over Probes' positions: neighbours of Probes[k] in EdgeStart[k]..EdgeStart[k+1]
        internal int[] EdgeTarget;  // neighbour point indices
        internal double ErrorSum;
        internal LeakWeighting Leaks;  // null: plain errors

        /// <summary>Each candidate's removal cost into <paramref name="cost"/>: the summed error change (ascending point
        /// order) at the points whose stencil weighed it, plus its own new error. The trial (<paramref name="remaining"/>:
        /// the probes without the candidates) is interpolated at those points only.</summary>
        internal void RemovalCosts(ReferenceLighting reference, ITetrahedralizer tetrahedralizer, int[] remaining,
            int[] candidates, double[] cost)
        {
            int n = reference.Count;
            var isCandidate = new bool[n];
            foreach (int c in candidates) isCandidate[c] = true;
            foreach (int c in candidates) cost[c] = 0.0;
            var owner = new int[n];
            var attributed = new List<int>();
            for (int p = 0; p < n; p++)
            {
                owner[p] = isCandidate[p] ? p : -1;
                for (int k = 0; k < 4 && owner[p] < 0; k++)
                {
                    int o = Owners[4 * p + k];
                    if (o >= 0 && isCandidate[o]) owner[p] = o;
                }
                if (owner[p] >= 0) attributed.Add(p);
            }
            var trialErrors = new double[n];
            var seen = Leaks == null ? null : new StencilLog();
            PlacementError.InterpolatePoints(reference, remaining, Tetrahedralize(reference, tetrahedralizer, remaining), attributed.ToArray(),
                (int p, ref Stencil stencil, double[] interpolated) =>
                {
                    trialErrors[p] = PointError(reference, p, interpolated);
                    seen?.Add(p, stencil);
                });
            seen?.Weigh(reference, remaining, Leaks, trialErrors);
            foreach (int p in attributed) cost[owner[p]] += trialErrors[p] - Errors[p];
        }

        /// <summary>The sorted <paramref name="probes"/> without <paramref name="removed"/>, in order.</summary>
        internal static int[] ProbesWithout(int[] probes, int[] removed, int n)
        {
            var gone = new bool[n];
            foreach (int r in removed) gone[r] = true;
            var kept = new List<int>(probes.Length);
            foreach (int p in probes)
                if (!gone[p]) kept.Add(p);
            return kept.ToArray();
        }

        /// <summary>Every point of <paramref name="probes"/> (sorted) evaluated: the seed.</summary>
        /// <param name="leaks">Weighs leaking points' errors from now on (null: plain errors).</param>
        internal static BatchedRefinementState Evaluate(ReferenceLighting reference, ITetrahedralizer tetrahedralizer, int[] probes,
            LeakWeighting leaks = null)
        {
            int n = reference.Count;
            var state = new BatchedRefinementState
            {
                Probes = probes, Errors = new double[n], Owners = new int[4 * n], Touched = new int[4 * n], Leaks = leaks
            };
            for (int i = 0; i < 4 * n; i++) state.Owners[i] = state.Touched[i] = -1;
            Relocate(reference, tetrahedralizer, state, null);
            return state;
        }

        /// <summary>The state of these probes without <paramref name="removed"/>: only the points whose
        /// stencil touched a removed probe (and the removed themselves) are interpolated again (class text).</summary>
        internal BatchedRefinementState Without(ReferenceLighting reference, ITetrahedralizer tetrahedralizer, int[] removed)
        {
            int n = reference.Count;
            var gone = new bool[n];
            foreach (int r in removed) gone[r] = true;
            var affected = new List<int>();
            for (int p = 0; p < n; p++)
            {
                bool touched = gone[p];
                for (int k = 0; k < 4 && !touched; k++)
                {
                    int o = Touched[4 * p + k];
                    touched = o >= 0 && gone[o];
                }
                if (touched) affected.Add(p);
            }
            var next = new BatchedRefinementState
            {
                Probes = ProbesWithout(Probes, removed, n), Errors = (double[])Errors.Clone(),
                Owners = (int[])Owners.Clone(), Touched = (int[])Touched.Clone(), Leaks = Leaks
            };
            Relocate(reference, tetrahedralizer, next, affected.ToArray());
            return next;
        }

        /// <summary>Tetrahedralises the state's probes and interpolates <paramref name="points"/> (ascending, none a probe;
        /// null: every point that is not a probe) into its errors, owners and touched probes; then its edges and error sum.</summary>
        private static void Relocate(ReferenceLighting reference, ITetrahedralizer tetrahedralizer, BatchedRefinementState state, int[] points)
        {
            int[] probes = state.Probes;
            int[] tetrahedra = Tetrahedralize(reference, tetrahedralizer, probes);
            double[] errors = state.Errors;
            int[] owners = state.Owners, touched = state.Touched;
            var seen = state.Leaks == null ? null : new StencilLog();
            PlacementError.InterpolatePoints(reference, probes, tetrahedra, points, (int p, ref Stencil stencil, double[] interpolated) =>
            {
                errors[p] = PointError(reference, p, interpolated);
                seen?.Add(p, stencil);
                touched[4 * p] = probes[stencil.Probe0];
                touched[4 * p + 1] = probes[stencil.Probe1];
                touched[4 * p + 2] = probes[stencil.Probe2];
                touched[4 * p + 3] = probes[stencil.Probe3];
                owners[4 * p] = stencil.Weight0 > 0 ? touched[4 * p] : -1;
                owners[4 * p + 1] = stencil.Weight1 > 0 ? touched[4 * p + 1] : -1;
                owners[4 * p + 2] = stencil.Weight2 > 0 ? touched[4 * p + 2] : -1;
                owners[4 * p + 3] = stencil.Weight3 > 0 ? touched[4 * p + 3] : -1;
            });
            seen?.Weigh(reference, probes, state.Leaks, errors);
            double sum = 0;
            foreach (double e in errors) sum += e;
            state.ErrorSum = sum;
            Edges(tetrahedra, probes, out state.EdgeStart, out state.EdgeTarget);
        }

        private static int[] Tetrahedralize(ReferenceLighting reference, ITetrahedralizer tetrahedralizer, int[] probes)
        {
            var positions = new Vector3[probes.Length];
            for (int k = 0; k < probes.Length; k++) positions[k] = reference.GetPosition(probes[k]);
            return tetrahedralizer.Tetrahedralize(positions);
        }

        /// <summary>The points an interpolation visited and their stencils, for the leak weighting after it.</summary>
        private sealed class StencilLog
        {
            private readonly List<int> points = new List<int>();
            private readonly List<Stencil> stencils = new List<Stencil>();

            internal void Add(int point, Stencil stencil)
            {
                points.Add(point);
                stencils.Add(stencil);
            }

            internal void Weigh(ReferenceLighting reference, int[] probes, LeakWeighting leaks, double[] errors) =>
                leaks.Weigh(reference, probes, points, stencils, errors);
        }

        private static double PointError(ReferenceLighting reference, int p, double[] interpolated) =>
            PointErrorMetrics.Irradiance(interpolated, reference.Light, p * ReferenceLighting.LightValues, reference.SceneScale);

        /// <summary>The Delaunay graph as CSR over the probe list: each tetrahedron's 6 edges, both ways, without repeats.</summary>
        private static void Edges(int[] tetrahedra, int[] probes, out int[] start, out int[] target)
        {
            int count = probes.Length;
            var keys = new List<long>(tetrahedra.Length * 3);
            for (int t = 0; t + 3 < tetrahedra.Length; t += 4)
                for (int a = 0; a < 4; a++)
                    for (int b = 0; b < 4; b++)
                        if (a != b) keys.Add((long)tetrahedra[t + a] * count + tetrahedra[t + b]);
            keys.Sort();
            start = new int[count + 1];
            var targets = new List<int>(keys.Count / 2);
            long previous = -1;
            foreach (long key in keys)
            {
                if (key == previous) continue;
                previous = key;
                start[(int)(key / count) + 1]++;
                targets.Add(probes[(int)(key % count)]);
            }
            for (int k = 0; k < count; k++) start[k + 1] += start[k];
            target = targets.ToArray();
        }
    }
}
