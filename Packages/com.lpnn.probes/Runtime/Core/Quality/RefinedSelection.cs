using System;
using System.Collections.Generic;
using System.Threading;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Selection;

namespace Lpnn.Probes.Core.Quality
{
    /// <summary>Refined insertion (Documentation~/quality.md §5.3): a selection made from an insertion ranking's prefixes,
    /// refined by <see cref="BatchedRefinement"/> — what a Unity volume's Apply does with the insertion methods. The seed
    /// is the ranking's first <see cref="BudgetSeedCount"/> points for a count policy (Budget, Spread, Percentile), which
    /// refines down to K, or <see cref="SeedCount"/> points for the tolerance policy, which refines as far as the error
    /// stays within τ, keeping the refined set only when it has fewer probes than the search's; plus whatever the
    /// selection holds (bounds corners, the tetrahedron guarantee), K being the selection's count; the bounds corners are
    /// kept. Port of lpnn/quality/placement/refined_insertion.py (same seeds, same refinement).</summary>
    public static class RefinedSelection
    {
        /// <summary>The seed holds this many times the selection's count (the refine tier's factor).</summary>
        public const double DefaultFactor = 2.0;

        /// <summary>A seed of 2K points cannot reach a sparse answer at tiny K (lpnn/quality/placement/lpnn_placement.py MINIMUM_SEED).</summary>
        public const int MinimumSeed = 64;

        /// <summary>A count policy's seed holds this many times <see cref="DefaultFactor"/> × K points (3K) while they are at most
        /// <see cref="BudgetSeedCap"/> × N: 2K points are too few at small budgets (the validation crops: 1.08× the reference's
        /// error at 5 %, 1.04× with 3K; Documentation~/benchmarks.md "A wider seed for small budgets"). refined_insertion.py BUDGET_SEED_WIDENING.</summary>
        public const double BudgetSeedWidening = 1.5;

        /// <summary>The wider seed stops growing at this share of the points, which 2K reaches at a 25 % budget: beyond it a wider
        /// seed costs much time for little (3K: +51 % CPU at 30 %; Documentation~/benchmarks.md "The budget seed's cap
        /// re-chosen"). refined_insertion.py BUDGET_SEED_CAP.</summary>
        public const double BudgetSeedCap = 0.5;

        /// <param name="selection">What the policy selected from <paramref name="prefix"/> (ProbeSelector.SelectFromPrefixes
        /// or SelectFromRanking with the same settings).</param>
        /// <param name="candidates">The points the whole ranking holds (the grid's, or its valid ones).</param>
        /// <param name="evaluator">The lighting of every grid point and the tetrahedraliser (Unity's in the editor).</param>
        public static SelectionResult Refine(EvaluationGrid grid, SelectionResult selection, RankingPrefix prefix, int candidates, SelectionSettings settings,
            PlacementEvaluator evaluator, bool[] valid = null, ProgressCallback progress = null, CancellationToken cancel = default) =>
            Refine(grid, selection, prefix, candidates, settings, evaluator, null, valid, progress, cancel);

        /// <summary>As the public overload; with <paramref name="leaks"/> (null: off) the leak-aware variant of
        /// lpnn/quality/placement/refined_insertion.py (Documentation~/leaks.md "A leak-aware default"): the seed gets
        /// <see cref="LeakRepair.DefaultRounds"/> repair rounds, the refinement weighs leaking points' errors, and with a
        /// tolerance the refined set is the answer whenever its weighted mean error is within τ, even with more probes than
        /// the search's (the price of fewer leaks). <paramref name="pins"/> (null: none; grid indices, pins.md): the refinement
        /// never removes them, a count policy's count must hold them, and the leak repair adds no probe within their keep
        /// distance (a leaking point there is left to the pinned probe).</summary>
        internal static SelectionResult Refine(EvaluationGrid grid, SelectionResult selection, RankingPrefix prefix, int candidates, SelectionSettings settings,
            PlacementEvaluator evaluator, LeakWeighting leaks, bool[] valid = null, ProgressCallback progress = null, CancellationToken cancel = default,
            Pins pins = null)
        {
            if (grid == null) throw new ArgumentNullException(nameof(grid));
            if (selection == null) throw new ArgumentNullException(nameof(selection));
            if (prefix == null) throw new ArgumentNullException(nameof(prefix));
            if (evaluator == null) throw new ArgumentNullException(nameof(evaluator));
            if (evaluator.Reference.Count != grid.Count)
                throw new PlacementErrorException("the reference lighting has " + evaluator.Reference.Count + " points but the grid has " + grid.Count +
                                                  "; sample the lighting for this grid");
            settings.Validate();
            if (settings.Policy == SelectionPolicy.Threshold)
                throw new SelectionException("batched refinement refines a ranking's prefix; the score threshold policy has none: choose Tolerance, Spread or Budget");
            int target = selection.Indices.Length;
            if (pins != null && settings.Policy != SelectionPolicy.Tolerance) pins.CheckCount(target);
            int seedCount = settings.Policy == SelectionPolicy.Tolerance ? SeedCount(target, candidates) : BudgetSeedCount(target, candidates);
            var seed = new HashSet<int>(selection.Indices);
            if (pins != null) seed.UnionWith(pins.Indices);
            int[] head = prefix(seedCount);
            for (int r = 0; r < seedCount && r < head.Length; r++) seed.Add(head[r]);
            if (leaks == null && seed.Count <= target) return selection;  // the seed is the selection: nothing to remove
            var seedPoints = new int[seed.Count];
            seed.CopyTo(seedPoints);
            var tetrahedralizer = evaluator.Tetrahedralizer;
            if (leaks != null)  // a leak of the seed could not be undone by a refinement that only removes probes
                seedPoints = LeakRepair.Repaired(evaluator.Reference, tetrahedralizer, seedPoints, leaks.Raycaster, LeakRepair.DefaultRounds, cancel,
                    pins?.Blocked, leaks.MemoFor(evaluator.Reference));
            var kept = new List<int>();
            if (settings.KeepBoundsCorners) kept.AddRange(ProbeSelector.BoundsCorners(grid, valid));
            if (pins != null) kept.AddRange(pins.Indices);
            int[] keep = kept.Count == 0 ? null : kept.ToArray();
            if (settings.Policy != SelectionPolicy.Tolerance)
            {
                var counted = BatchedRefinement.ToCount(evaluator.Reference, tetrahedralizer, seedPoints, target, leaks, keep, progress, cancel);
                return new SelectionResult(counted.Indices, selection.CornersAdded, 0, null, seedPoints.Length);
            }
            var refined = BatchedRefinement.WithinTolerance(evaluator.Reference, tetrahedralizer, seedPoints, settings.Value, leaks, keep, progress, cancel);
            // Leak-aware: the weighted tolerance met is the goal, whatever the count; else fewer probes than the search's.
            // The refinement's error is updated incrementally, exact only for the unique tie-broken Delaunay of our stand-in;
            // Unity's native tetrahedraliser may split co-spherical points differently (issue 31), so the final set is
            // evaluated once, from scratch, with the same tetrahedraliser Apply's preview uses, before it replaces the search's.
            bool better = refined.MeanError <= settings.Value && (leaks != null || refined.Indices.Length < target) &&
                          evaluator.MeanError(refined.Indices) <= settings.Value;
            return better ? new SelectionResult(refined.Indices, selection.CornersAdded, 0, selection.Tolerance, seedPoints.Length) : selection;
        }

        /// <summary>The tolerance policy's seed: min(N, max(round(F K), <see cref="MinimumSeed"/>)), halves up.</summary>
        public static int SeedCount(int count, int candidates) =>
            Math.Min(candidates, Math.Max(Rounded(DefaultFactor * count), MinimumSeed));

        /// <summary>A count policy's seed: min(N, max(round(F K), min(round(1.5 F K), round(0.5 N)), <see cref="MinimumSeed"/>)),
        /// halves up (1.5 = <see cref="BudgetSeedWidening"/>, 0.5 = <see cref="BudgetSeedCap"/>): 3K for small budgets, at most
        /// 0.5 N, never fewer than 2K.</summary>
        public static int BudgetSeedCount(int count, int candidates) =>
            Math.Min(candidates, Math.Max(SeedCount(count, candidates),
                Math.Min(Rounded(BudgetSeedWidening * DefaultFactor * count), Rounded(BudgetSeedCap * candidates))));

        private static int Rounded(double value) => (int)Math.Floor(value + 0.5);
    }
}
