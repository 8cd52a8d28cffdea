using System;
using System.Collections.Generic;
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
    /// lpnn/quality/placement/batched_refinement.py (the same rounds, irradiance metric); parity pinned by
    /// Tests/Data/batched_refinement_golden.json.
    ///
    /// A round from the probe set P: (1) candidates = the greedy independent set of P's Delaunay graph by measured cost
    /// (costs not fresh — never measured, or a neighbour removed since — first; costs within <see cref="InsertionRanking.Tie"/>
    /// of each other: lower index), locked probes left
    /// out, at most |P| − 4; if the rest is flat, only the first unlocked probe whose removal alone leaves a solid set; (2) one trial
    /// without them gives each its cost — but a candidate whose cost is fresh and that lies on no face without a tetrahedron
    /// across keeps its cost and stays out of the trial (<see cref="BatchedRefinementState.BoundaryVertices"/>: the trial
    /// would measure the same number up to rounding); (3) commit those within the
    /// <see cref="CountCommitFraction"/> (down to a count) or <see cref="ToleranceCommitFraction"/> (within a tolerance) quantile of all measured costs, cheapest first (none: the cheapest candidate once
    /// every cost is fresh), capped by the count, or the longest prefix that keeps the error sum within τ·N (nothing
    /// committed: with a tolerance and every cost fresh, stop; else go on); (4) their neighbours' costs go stale; the new set is evaluated, and with a tolerance an overshoot
    /// (a hull vertex's effect on points outside, not attributed) brings the dearest removed probes back, locked.
    /// Each round: the trial's and the committed set's tetrahedra derived from the candidates' star refills, not tetrahedralised
    /// (<see cref="BatchedRefinementState"/>, <see cref="StarRefills"/>); only the points whose stencil held a removed probe are interpolated
    /// again (the tie-broken Delaunay is unique: every other tetrahedron survives a removal, and a point outside the hull
    /// keeps its nearest hull point unless that point's triangle had a removed vertex).</summary>
    public static class BatchedRefinement
    {
        /// <summary>Down to a count, commit the candidates within this quantile of the measured costs (chosen on validation
        /// crops and levels, quality.md §5.3).</summary>
        public const double CountCommitFraction = 0.05;

        /// <summary>Within a tolerance, commit the candidates within this quantile of the measured costs (chosen on validation
        /// crops and levels, quality.md §5.3: as few probes as 0.05 on the crops, in fewer rounds).</summary>
        public const double ToleranceCommitFraction = 0.1;

        /// <summary>A set thinner than this fraction of its extent is flat (lpnn/quality/metric/triangulation.py FLAT_TOLERANCE).</summary>
        public const double FlatTolerance = 1e-7;

        private const string Stage = "batched refinement";

        /// <summary>Down to <paramref name="count"/> probes (at least 4).</summary>
        /// <param name="seed">Evaluation point indices (distinct, at least 4, not in one plane).</param>
        /// <param name="keep">Point indices never removed (e.g. the bounds corners), or null.</param>
        public static BatchedRefinementResult ToCount(ReferenceLighting reference, ITetrahedralizer tetrahedralizer, int[] seed, int count,
            int[] keep = null, ProgressCallback progress = null, CancellationToken cancel = default, double fraction = CountCommitFraction) =>
            ToCount(reference, tetrahedralizer, seed, count, null, keep, progress, cancel, fraction);

        /// <summary>As the public overload; with <paramref name="leaks"/> (null: off) every error the rounds sum is the
        /// leak-weighted one (Documentation~/leaks.md "A leak-aware default"), the result's mean error included.</summary>
        internal static BatchedRefinementResult ToCount(ReferenceLighting reference, ITetrahedralizer tetrahedralizer, int[] seed, int count,
            LeakWeighting leaks, int[] keep = null, ProgressCallback progress = null, CancellationToken cancel = default, double fraction = CountCommitFraction)
        {
            if (count < 1) throw new PlacementErrorException("the count to refine down to must be at least 1, got " + count);
            return Run(reference, tetrahedralizer, seed, Math.Max(ProbeIndices.Minimum, count), double.NaN, keep, progress, cancel, fraction, leaks);
        }

        /// <summary>As far as the mean irradiance error stays ≤ <paramref name="tolerance"/>. A seed already above it comes
        /// back unrefined (<see cref="BatchedRefinementResult.SeedAboveTolerance"/>).</summary>
        public static BatchedRefinementResult WithinTolerance(ReferenceLighting reference, ITetrahedralizer tetrahedralizer, int[] seed, double tolerance,
            int[] keep = null, ProgressCallback progress = null, CancellationToken cancel = default, double fraction = ToleranceCommitFraction) =>
            WithinTolerance(reference, tetrahedralizer, seed, tolerance, null, keep, progress, cancel, fraction);

        /// <summary>As the public overload; with <paramref name="leaks"/> (null: off) the tolerance bounds the leak-weighted
        /// mean error, and the result's mean error is that one (Documentation~/leaks.md "A leak-aware default").</summary>
        internal static BatchedRefinementResult WithinTolerance(ReferenceLighting reference, ITetrahedralizer tetrahedralizer, int[] seed, double tolerance,
            LeakWeighting leaks, int[] keep = null, ProgressCallback progress = null, CancellationToken cancel = default, double fraction = ToleranceCommitFraction)
        {
            if (!(tolerance > 0) || double.IsInfinity(tolerance))
                throw new PlacementErrorException("tolerance " + InvariantFormat.Number(tolerance) + " must be a finite mean error > 0 (e.g. 0.05)");
            return Run(reference, tetrahedralizer, seed, ProbeIndices.Minimum, tolerance, keep, progress, cancel, fraction, leaks);
        }

        private static BatchedRefinementResult Run(ReferenceLighting reference, ITetrahedralizer tetrahedralizer, int[] seed, int goal, double tolerance,
            int[] keep, ProgressCallback progress, CancellationToken cancel, double fraction, LeakWeighting leaks)
        {
            if (reference == null) throw new ArgumentNullException(nameof(reference));
            if (tetrahedralizer == null) throw new ArgumentNullException(nameof(tetrahedralizer));
            if (!(fraction >= 0 && fraction <= 1))
                throw new PlacementErrorException("commit fraction " + InvariantFormat.Number(fraction) + " must be in [0, 1] (e.g. " +
                                                  InvariantFormat.Number(ToleranceCommitFraction) + ")");
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
            var state = BatchedRefinementState.Evaluate(reference, tetrahedralizer, probes, leaks);
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
                int[] remaining = BatchedRefinementState.ProbesWithout(current, candidates, n);
                if (IsFlat(reference, remaining))
                {
                    // Near the end only: the first unlocked probe in the candidates' order whose removal alone leaves a solid
                    // set. A probe whose removal flattens the set flattens every subset too: it is locked for good.
                    int solid = -1;
                    foreach (int c in Candidates(state, cost, fresh, locked, int.MaxValue, independent: false))
                    {
                        if (!IsFlat(reference, BatchedRefinementState.ProbesWithout(current, new[] { c }, n))) { solid = c; break; }
                        locked[c] = true;
                    }
                    if (solid < 0)
                    {
                        stop = BatchedRefinementResult.StoppedFlat;
                        break;
                    }
                    candidates = new[] { solid };
                }
                rounds++;
                int[] measure = RemeasureFreshCostsForTests ? candidates : StaleOrOnTheBoundary(state, candidates, fresh, n);
                TrialListener?.Invoke(candidates.Length, measure.Length);
                if (measure.Length > 0)
                    state.RemovalCosts(reference, tetrahedralizer, BatchedRefinementState.ProbesWithout(current, measure, n), measure, cost);
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
                var following = state.Without(reference, tetrahedralizer, commit.ToArray());
                int back = commit.Count;
                while (byTolerance && following.ErrorSum > limit && back > 0)  // an unattributed hull effect
                {
                    cancel.ThrowIfCancellationRequested();  // each retry is a tetrahedralisation and an evaluation (issue 31)
                    back--;
                    locked[commit[back]] = true;
                    following = state.Without(reference, tetrahedralizer, commit.GetRange(0, back).ToArray());
                }
                state = following;
                progress?.Invoke(Stage, seeded - state.Probes.Length, seeded - goal);
                cancel.ThrowIfCancellationRequested();  // a Cancel pressed in the progress call stops before the next round
            }
            return new BatchedRefinementResult(state.Probes, state.ErrorSum / n, rounds, stop);
        }

        /// <summary>Tests only: every candidate's cost measured in every trial, fresh or not (as before 2026-11-28; the
        /// refinement must then keep the same probes). Per thread, so that a test cannot leak it into another's run.</summary>
        [ThreadStatic] internal static bool RemeasureFreshCostsForTests;

        /// <summary>Tests only: told each round's count of candidates and of those whose cost the trial measured.</summary>
        [ThreadStatic] internal static Action<int, int> TrialListener;

        /// <summary>The candidates whose cost a trial must measure: not fresh, or a probe on the boundary
        /// (<see cref="BatchedRefinementState.BoundaryVertices"/>), in the candidates' order.</summary>
        private static int[] StaleOrOnTheBoundary(BatchedRefinementState state, int[] candidates, bool[] fresh, int n)
        {
            bool[] boundary = state.BoundaryVertices(n);
            var measure = new List<int>(candidates.Length);
            foreach (int c in candidates)
                if (!fresh[c] || boundary[c]) measure.Add(c);
            return measure.ToArray();
        }

        /// <summary>The greedy independent set by (cost, index) among the unlocked probes, costs that are not fresh (never
        /// measured, or a neighbour removed since) counting as −∞, in that order; at most <paramref name="limit"/>.</summary>
        /// <param name="independent">False: every unlocked probe in that order (no neighbour is skipped).</param>
        private static int[] Candidates(BatchedRefinementState state, double[] cost, bool[] fresh, bool[] locked, int limit, bool independent = true)
        {
            int[] probes = state.Probes;
            var unlocked = new List<int>(probes.Length);  // positions in probes
            for (int k = 0; k < probes.Length; k++)
                if (!locked[probes[k]]) unlocked.Add(k);
            var ids = new int[unlocked.Count];
            var key = new double[unlocked.Count];
            for (int u = 0; u < ids.Length; u++)
            {
                ids[u] = probes[unlocked[u]];
                key[u] = fresh[ids[u]] ? cost[ids[u]] : double.NegativeInfinity;
            }
            var blocked = new bool[probes.Length];
            var chosen = new List<int>();
            foreach (int u in CheapestFirst(key, ids))
            {
                int k = unlocked[u];
                if (blocked[k] && independent) continue;
                chosen.Add(probes[k]);
                for (int e = state.EdgeStart[k]; e < state.EdgeStart[k + 1]; e++)
                    blocked[Array.BinarySearch(probes, state.EdgeTarget[e])] = true;  // every neighbour is a probe
                blocked[k] = true;
                if (chosen.Count == limit) break;
            }
            return chosen.ToArray();
        }

        /// <summary>The candidates within the <paramref name="fraction"/> quantile (lower, no interpolation) of the measured
        /// costs of <paramref name="probes"/>, cheapest first (ties within the band: lower index); when none is and every cost is fresh
        /// (<paramref name="settled"/>), the cheapest candidate. Costs within <see cref="InsertionRanking.Tie"/> are equal (<see cref="CheapestFirst"/>).</summary>
        private static List<int> Commit(int[] candidates, double[] cost, int[] probes, double fraction, bool settled)
        {
            var measured = new List<double>(probes.Length);
            foreach (int p in probes)
                if (!double.IsInfinity(cost[p]) && !double.IsNaN(cost[p])) measured.Add(cost[p]);
            measured.Sort();
            double threshold = measured[(int)Math.Floor(fraction * (measured.Count - 1))];
            var candidateCost = new double[candidates.Length];
            for (int k = 0; k < candidates.Length; k++) candidateCost[k] = cost[candidates[k]];
            int[] ordered = CheapestFirst(candidateCost, candidates);
            var commit = new List<int>();
            foreach (int k in ordered)
                if (candidateCost[k] <= threshold + InsertionRanking.Tie) commit.Add(candidates[k]);  // tied with the threshold: within it
            if (commit.Count == 0 && settled) commit.Add(candidates[ordered[0]]);
            return commit;
        }

        /// <summary>Positions of <paramref name="costs"/>, cheapest first, where a cost within <see cref="InsertionRanking.Tie"/>
        /// of the next cheaper one counts as equal to it: each run of such costs goes by <paramref name="ids"/>, lowest first.
        /// The same removal's cost from the same tetrahedra listed in another vertex order differs in the last bits, and many
        /// costs are exactly 0 where the light is even: compared exactly, such ties would be decided by rounding, and Unity's
        /// tetrahedraliser and Qhull would commit differently (quality.md §5.3 "Ties"; Python's
        /// batched_refinement.cheapest_first).</summary>
        internal static int[] CheapestFirst(double[] costs, int[] ids)
        {
            var negated = new double[costs.Length];
            for (int k = 0; k < costs.Length; k++) negated[k] = -costs[k];
            return InsertionRanking.LargestFirst(negated, ids);
        }

        private static void MarkNeighboursStale(BatchedRefinementState state, List<int> removed, bool[] fresh)
        {
            foreach (int r in removed)
            {
                int k = Array.BinarySearch(state.Probes, r);  // the probes are sorted
                for (int e = state.EdgeStart[k]; e < state.EdgeStart[k + 1]; e++) fresh[state.EdgeTarget[e]] = false;
            }
        }

        /// <summary>Whether the points lie (within <see cref="FlatTolerance"/> of their extent) on one line or in one plane:
        /// the farthest point from the first, the farthest from that line, the farthest from that plane.</summary>
        internal static bool IsFlat(ReferenceLighting reference, int[] points)
        {
            if (points.Length < 4) return true;
            double[] local = reference.Local;
            var origin = Double3.FromTriples(local, points[0]);
            Double3 far = origin;
            double extent = 0;
            foreach (int p in points)
            {
                double d = (Double3.FromTriples(local, p) - origin).Length;
                if (d > extent) { extent = d; far = Double3.FromTriples(local, p); }
            }
            if (!(extent > 0)) return true;
            var axis = (far - origin) * (1.0 / extent);
            Double3 normal = default;
            double offLine = 0;
            foreach (int p in points)
            {
                var r = Double3.FromTriples(local, p) - origin;
                var across = r - axis * Double3.Dot(r, axis);
                double d = across.Length;
                if (d > offLine) { offLine = d; normal = across; }
            }
            if (offLine <= FlatTolerance * extent) return true;
            var planeNormal = Double3.Cross(axis, normal * (1.0 / offLine));
            double length = planeNormal.Length;
            foreach (int p in points)
                if (Math.Abs(Double3.Dot(Double3.FromTriples(local, p) - origin, planeNormal)) / length > FlatTolerance * extent) return false;
            return true;
        }
    }
}
