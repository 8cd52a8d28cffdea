using System;
using System.Collections.Generic;
using System.Numerics;
using System.Threading;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Core.Quality
{
    /// <summary>Batched refinement (Documentation~/quality.md §5.3): greedy decimation of a seed set by whole independent
    /// sets of probes, so that a Unity volume gets within ~1.1× of the reference's probe count with nothing but the
    /// tetrahedraliser, point location and error it already has. Two probes that share no Delaunay edge share no
    /// tetrahedron, so removing an independent set and tetrahedralising once gives every member's exact removal cost;
    /// costs of an independent set add up, so any subset can be committed with a known error. Port of
    /// lpnn/quality/batched_refinement.py (the same rounds, irradiance metric); parity pinned by
    /// Tests/Data/batched_refinement_golden.json.
    ///
    /// A round from the probe set P: (1) candidates = the greedy independent set of P's Delaunay graph by measured cost
    /// (costs not fresh — never measured, or a neighbour removed since — first; ties: lower index), locked probes left
    /// out, at most |P| − 4; if the rest is flat, only the first unlocked probe whose removal alone leaves a solid set; (2) one trial
    /// without them gives each its cost; (3) commit those within the
    /// <see cref="CommitFraction"/> quantile of all measured costs, cheapest first (none: the cheapest candidate once
    /// every cost is fresh), capped by the count, or the longest prefix that keeps the error sum within τ·N (nothing
    /// committed: with a tolerance and every cost fresh, stop; else go on); (4) their neighbours' costs go stale; the new set is evaluated, and with a tolerance an overshoot
    /// (a hull vertex's effect on points outside, not attributed) brings the dearest removed probes back, locked.
    /// Each round: two tetrahedralisations of the probes; only the points whose stencil held a removed probe are interpolated
    /// again (the tie-broken Delaunay is unique: every other tetrahedron survives a removal, and a point outside the hull
    /// keeps its nearest hull point unless that point's triangle had a removed vertex).</summary>
    public static class BatchedRefinement
    {
        /// <summary>Commit the candidates within this quantile of the measured costs (chosen on validation crops and levels,
        /// quality.md §5.3).</summary>
        public const double CommitFraction = 0.05;

        /// <summary>A set thinner than this fraction of its extent is flat (lpnn/quality/triangulation.py FLAT_TOLERANCE).</summary>
        public const double FlatTolerance = 1e-7;

        private const string Stage = "batched refinement";

        /// <summary>Down to <paramref name="count"/> probes (at least 4).</summary>
        /// <param name="seed">Evaluation point indices (distinct, at least 4, not in one plane).</param>
        /// <param name="keep">Point indices never removed (e.g. the bounds corners), or null.</param>
        public static BatchedRefinementResult ToCount(ReferenceLighting reference, ITetrahedralizer tetrahedralizer, int[] seed, int count,
            int[] keep = null, ProgressCallback progress = null, CancellationToken cancel = default, double fraction = CommitFraction)
        {
            if (count < 1) throw new PlacementErrorException("the count to refine down to must be at least 1, got " + count);
            return Run(reference, tetrahedralizer, seed, Math.Max(ProbeIndices.Minimum, count), double.NaN, keep, progress, cancel, fraction);
        }

        /// <summary>As far as the mean irradiance error stays ≤ <paramref name="tolerance"/>. A seed already above it comes
        /// back unrefined (<see cref="BatchedRefinementResult.SeedAboveTolerance"/>).</summary>
        public static BatchedRefinementResult WithinTolerance(ReferenceLighting reference, ITetrahedralizer tetrahedralizer, int[] seed, double tolerance,
            int[] keep = null, ProgressCallback progress = null, CancellationToken cancel = default, double fraction = CommitFraction)
        {
            if (!(tolerance > 0) || double.IsInfinity(tolerance))
                throw new PlacementErrorException("tolerance " + InvariantFormat.Number(tolerance) + " must be a finite mean error > 0 (e.g. 0.05)");
            return Run(reference, tetrahedralizer, seed, ProbeIndices.Minimum, tolerance, keep, progress, cancel, fraction);
        }

        private sealed class MeshState
        {
            public int[] Probes;      // sorted evaluation point indices
            public double[] Errors;   // per point, 0 at the probes
            public int[] Owners;      // 4 per point: the probes (point indices) its stencil weighs > 0, else -1
            public int[] Touched;     // 4 per point: every probe (point index) of its stencil, zero weights included; -1 at probes
            public int[] EdgeStart;   // CSR over Probes' positions: neighbours of Probes[k] in EdgeStart[k]..EdgeStart[k+1]
            public int[] EdgeTarget;  // neighbour point indices
            public double ErrorSum;
        }

        private static BatchedRefinementResult Run(ReferenceLighting reference, ITetrahedralizer tetrahedralizer, int[] seed, int goal, double tolerance,
            int[] keep, ProgressCallback progress, CancellationToken cancel, double fraction)
        {
            if (reference == null) throw new ArgumentNullException(nameof(reference));
            if (tetrahedralizer == null) throw new ArgumentNullException(nameof(tetrahedralizer));
            if (!(fraction >= 0 && fraction <= 1))
                throw new PlacementErrorException("commit fraction " + InvariantFormat.Number(fraction) + " must be in [0, 1] (e.g. " +
                                                  InvariantFormat.Number(CommitFraction) + ")");
            ProbeIndices.Check(seed, reference.Count);
            int n = reference.Count;
            bool byTolerance = !double.IsNaN(tolerance);
            double limit = byTolerance ? tolerance * n : double.PositiveInfinity;
            var locked = new bool[n];
            if (keep != null)
                foreach (int p in keep)
                {
                    if ((uint)p >= (uint)n) throw new PlacementErrorException("kept point " + p + " is outside the " + InvariantFormat.Count(n) + " evaluation points");
                    locked[p] = true;
                }
            var probes = (int[])seed.Clone();
            Array.Sort(probes);
            var state = Evaluate(reference, tetrahedralizer, probes);
            if (byTolerance && state.ErrorSum > limit)
                return new BatchedRefinementResult(state.Probes, state.ErrorSum / n, 0, BatchedRefinementResult.SeedAboveTolerance);
            var cost = new double[n];
            for (int p = 0; p < n; p++) cost[p] = double.NegativeInfinity;  // never measured: candidates first
            var fresh = new bool[n];
            int seeded = state.Probes.Length, rounds = 0;
            string stop;
            while (true)
            {
                cancel.ThrowIfCancellationRequested();
                int[] current = state.Probes;
                if (current.Length <= goal)
                {
                    stop = byTolerance ? BatchedRefinementResult.StoppedAtMinimum : BatchedRefinementResult.StoppedAtCount;
                    break;
                }
                int[] candidates = Candidates(state, cost, fresh, locked, current.Length - ProbeIndices.Minimum);
                if (candidates.Length == 0)
                {
                    stop = BatchedRefinementResult.StoppedAtTolerance;  // every probe left is locked
                    break;
                }
                int[] remaining = Without(current, candidates, n);
                if (IsFlat(reference, remaining))
                {
                    // Near the end only: the first unlocked probe in the candidates' order whose removal alone leaves a solid
                    // set. A probe whose removal flattens the set flattens every subset too: it is locked for good.
                    int solid = -1;
                    foreach (int c in Candidates(state, cost, fresh, locked, int.MaxValue, independent: false))
                    {
                        if (!IsFlat(reference, Without(current, new[] { c }, n))) { solid = c; break; }
                        locked[c] = true;
                    }
                    if (solid < 0)
                    {
                        stop = BatchedRefinementResult.StoppedFlat;
                        break;
                    }
                    candidates = new[] { solid };
                    remaining = Without(current, candidates, n);
                }
                rounds++;
                RemovalCosts(reference, tetrahedralizer, state, remaining, candidates, cost);
                foreach (int c in candidates) fresh[c] = true;
                bool settled = true;  // every unlocked probe's cost is fresh
                foreach (int p in current) settled &= fresh[p] || locked[p];
                var commit = Commit(candidates, cost, current, fraction, settled);
                if (!byTolerance && commit.Count > current.Length - goal) commit.RemoveRange(current.Length - goal, commit.Count - (current.Length - goal));
                if (byTolerance)
                {
                    double sum = state.ErrorSum;
                    int fits = 0;
                    while (fits < commit.Count && sum + cost[commit[fits]] <= limit) sum += cost[commit[fits++]];
                    commit.RemoveRange(fits, commit.Count - fits);
                }
                if (commit.Count == 0)
                {
                    if (byTolerance && settled)
                    {
                        stop = BatchedRefinementResult.StoppedAtTolerance;
                        break;
                    }
                    continue;  // the stale costs are candidates first next round
                }
                MarkNeighboursStale(state, commit, fresh);
                var following = WithoutProbes(reference, tetrahedralizer, state, commit.ToArray());
                int back = commit.Count;
                while (byTolerance && following.ErrorSum > limit && back > 0)  // an unattributed hull effect
                {
                    back--;
                    locked[commit[back]] = true;
                    following = WithoutProbes(reference, tetrahedralizer, state, commit.GetRange(0, back).ToArray());
                }
                state = following;
                progress?.Invoke(Stage, seeded - state.Probes.Length, seeded - goal);
            }
            return new BatchedRefinementResult(state.Probes, state.ErrorSum / n, rounds, stop);
        }

        /// <summary>The greedy independent set by (cost, index) among the unlocked probes, costs that are not fresh (never
        /// measured, or a neighbour removed since) counting as −∞, in that order; at most <paramref name="limit"/>.</summary>
        /// <param name="independent">False: every unlocked probe in that order (no neighbour is skipped).</param>
        private static int[] Candidates(MeshState state, double[] cost, bool[] fresh, bool[] locked, int limit, bool independent = true)
        {
            int[] probes = state.Probes;
            var order = new List<int>(probes.Length);  // positions in probes
            for (int k = 0; k < probes.Length; k++)
                if (!locked[probes[k]]) order.Add(k);
            var key = new double[probes.Length];
            for (int k = 0; k < probes.Length; k++) key[k] = fresh[probes[k]] ? cost[probes[k]] : double.NegativeInfinity;
            order.Sort((a, b) =>
            {
                int byCost = key[a].CompareTo(key[b]);
                return byCost != 0 ? byCost : probes[a].CompareTo(probes[b]);
            });
            var blocked = new bool[probes.Length];
            var chosen = new List<int>();
            foreach (int k in order)
            {
                if (blocked[k] && independent) continue;
                chosen.Add(probes[k]);
                for (int e = state.EdgeStart[k]; e < state.EdgeStart[k + 1]; e++)
                    blocked[Array.BinarySearch(probes, state.EdgeTarget[e])] = true;  // every neighbour is a probe
                blocked[k] = true;
                if (chosen.Count == limit) break;
            }
            return chosen.ToArray();
        }

        /// <summary>Each candidate's removal cost: the summed error change (ascending point order) at the points whose
        /// stencil weighed it, plus its own new error. The trial (<paramref name="remaining"/>: the probes without the
        /// candidates) is interpolated at those points only.</summary>
        private static void RemovalCosts(ReferenceLighting reference, ITetrahedralizer tetrahedralizer, MeshState state, int[] remaining,
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
                    int o = state.Owners[4 * p + k];
                    if (o >= 0 && isCandidate[o]) owner[p] = o;
                }
                if (owner[p] >= 0) attributed.Add(p);
            }
            var trialErrors = new double[n];
            PlacementError.InterpolatePoints(reference, remaining, Tetrahedralize(reference, tetrahedralizer, remaining), attributed.ToArray(),
                (int p, ref Stencil stencil, double[] interpolated) => trialErrors[p] = PointError(reference, p, interpolated));
            foreach (int p in attributed) cost[owner[p]] += trialErrors[p] - state.Errors[p];
        }

        /// <summary>The candidates within the <paramref name="fraction"/> quantile (lower, no interpolation) of the measured
        /// costs of <paramref name="probes"/>, cheapest first (ties: lower index); when none is and every cost is fresh
        /// (<paramref name="settled"/>), the cheapest candidate.</summary>
        private static List<int> Commit(int[] candidates, double[] cost, int[] probes, double fraction, bool settled)
        {
            var measured = new List<double>(probes.Length);
            foreach (int p in probes)
                if (!double.IsInfinity(cost[p]) && !double.IsNaN(cost[p])) measured.Add(cost[p]);
            measured.Sort();
            double threshold = measured[(int)Math.Floor(fraction * (measured.Count - 1))];
            var ordered = (int[])candidates.Clone();
            Array.Sort(ordered, (a, b) =>
            {
                int byCost = cost[a].CompareTo(cost[b]);
                return byCost != 0 ? byCost : a.CompareTo(b);
            });
            var commit = new List<int>();
            foreach (int c in ordered)
                if (cost[c] <= threshold) commit.Add(c);
            if (commit.Count == 0 && settled) commit.Add(ordered[0]);
            return commit;
        }

        private static void MarkNeighboursStale(MeshState state, List<int> removed, bool[] fresh)
        {
            foreach (int r in removed)
            {
                int k = Array.BinarySearch(state.Probes, r);  // the probes are sorted
                for (int e = state.EdgeStart[k]; e < state.EdgeStart[k + 1]; e++) fresh[state.EdgeTarget[e]] = false;
            }
        }

        private static int[] Without(int[] probes, int[] removed, int n)
        {
            var gone = new bool[n];
            foreach (int r in removed) gone[r] = true;
            var kept = new List<int>(probes.Length);
            foreach (int p in probes)
                if (!gone[p]) kept.Add(p);
            return kept.ToArray();
        }

        /// <summary>Every point of <paramref name="probes"/> (sorted) evaluated: the seed.</summary>
        private static MeshState Evaluate(ReferenceLighting reference, ITetrahedralizer tetrahedralizer, int[] probes)
        {
            int n = reference.Count;
            var state = new MeshState { Probes = probes, Errors = new double[n], Owners = new int[4 * n], Touched = new int[4 * n] };
            for (int i = 0; i < 4 * n; i++) state.Owners[i] = state.Touched[i] = -1;
            Relocate(reference, tetrahedralizer, state, null);
            return state;
        }

        /// <summary>The state of <paramref name="state"/>'s probes without <paramref name="removed"/>: only the points whose
        /// stencil touched a removed probe (and the removed themselves) are interpolated again (class text).</summary>
        private static MeshState WithoutProbes(ReferenceLighting reference, ITetrahedralizer tetrahedralizer, MeshState state, int[] removed)
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
                    int o = state.Touched[4 * p + k];
                    touched = o >= 0 && gone[o];
                }
                if (touched) affected.Add(p);
            }
            var next = new MeshState
            {
                Probes = Without(state.Probes, removed, n), Errors = (double[])state.Errors.Clone(),
                Owners = (int[])state.Owners.Clone(), Touched = (int[])state.Touched.Clone()
            };
            Relocate(reference, tetrahedralizer, next, affected.ToArray());
            return next;
        }

        /// <summary>Tetrahedralises the state's probes and interpolates <paramref name="points"/> (ascending, none a probe;
        /// null: every point that is not a probe) into its errors, owners and touched probes; then its edges and error sum.</summary>
        private static void Relocate(ReferenceLighting reference, ITetrahedralizer tetrahedralizer, MeshState state, int[] points)
        {
            int[] probes = state.Probes;
            int[] tetrahedra = Tetrahedralize(reference, tetrahedralizer, probes);
            double[] errors = state.Errors;
            int[] owners = state.Owners, touched = state.Touched;
            PlacementError.InterpolatePoints(reference, probes, tetrahedra, points, (int p, ref Stencil stencil, double[] interpolated) =>
            {
                errors[p] = PointError(reference, p, interpolated);
                touched[4 * p] = probes[stencil.Probe0];
                touched[4 * p + 1] = probes[stencil.Probe1];
                touched[4 * p + 2] = probes[stencil.Probe2];
                touched[4 * p + 3] = probes[stencil.Probe3];
                owners[4 * p] = stencil.Weight0 > 0 ? touched[4 * p] : -1;
                owners[4 * p + 1] = stencil.Weight1 > 0 ? touched[4 * p + 1] : -1;
                owners[4 * p + 2] = stencil.Weight2 > 0 ? touched[4 * p + 2] : -1;
                owners[4 * p + 3] = stencil.Weight3 > 0 ? touched[4 * p + 3] : -1;
            });
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

        /// <summary>Whether the points lie (within <see cref="FlatTolerance"/> of their extent) on one line or in one plane:
        /// the farthest point from the first, the farthest from that line, the farthest from that plane.</summary>
        internal static bool IsFlat(ReferenceLighting reference, int[] points)
        {
            if (points.Length < 4) return true;
            double[] local = reference.Local;
            var origin = Point(local, points[0]);
            Double3 far = origin;
            double extent = 0;
            foreach (int p in points)
            {
                double d = (Point(local, p) - origin).Length;
                if (d > extent) { extent = d; far = Point(local, p); }
            }
            if (!(extent > 0)) return true;
            var axis = (far - origin) * (1.0 / extent);
            Double3 normal = default;
            double offLine = 0;
            foreach (int p in points)
            {
                var r = Point(local, p) - origin;
                var across = r - axis * Double3.Dot(r, axis);
                double d = across.Length;
                if (d > offLine) { offLine = d; normal = across; }
            }
            if (offLine <= FlatTolerance * extent) return true;
            var planeNormal = Double3.Cross(axis, normal * (1.0 / offLine));
            double length = planeNormal.Length;
            foreach (int p in points)
                if (Math.Abs(Double3.Dot(Point(local, p) - origin, planeNormal)) / length > FlatTolerance * extent) return false;
            return true;
        }

        private static Double3 Point(double[] local, int p) => new Double3(local[3 * p], local[3 * p + 1], local[3 * p + 2]);
    }
}
