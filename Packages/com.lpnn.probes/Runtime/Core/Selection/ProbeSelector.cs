using System;
using System.Collections.Generic;
using Lpnn.Probes.Core.Grid;

namespace Lpnn.Probes.Core.Selection
{
    /// <summary>The probes chosen from a grid: point indices sorted ascending, and what was added on top of
    /// the policy to keep the bounds corners and to guarantee a tetrahedron.</summary>
    public sealed class SelectionResult
    {
        public int[] Indices { get; }
        public int CornersAdded { get; }
        public int AddedForTetrahedron { get; }

        /// <summary>The tolerance policy's search (the count it settled on and every error it measured); null for
        /// the other policies.</summary>
        public ToleranceSearchResult Tolerance { get; }

        /// <summary>How many probes the seed of a batched refinement held (Quality.RefinedSelection: two to three times the policy's
        /// count); 0 when the selection was not refined.</summary>
        public int RefinedFrom { get; }

        public SelectionResult(int[] indices, int cornersAdded, int addedForTetrahedron)
            : this(indices, cornersAdded, addedForTetrahedron, null) { }

        public SelectionResult(int[] indices, int cornersAdded, int addedForTetrahedron, ToleranceSearchResult tolerance, int refinedFrom = 0)
        {
            Indices = indices;
            CornersAdded = cornersAdded;
            AddedForTetrahedron = addedForTetrahedron;
            Tolerance = tolerance;
            RefinedFrom = refinedFrom;
        }
    }

    /// <summary>Applies a selection policy to per-point scores (Documentation~/selection.md).</summary>
    public static class ProbeSelector
    {
        /// <summary>K = floor((1 − p)·N + 0.5 + 1e-9): "0.9 keeps the top 10 %", rounded to the nearest point, halves
        /// up; the 1e-9 absorbs binary rounding ((1 − 0.9)·125 + 0.5 is 12.999… in double).</summary>
        public static int PercentileCount(double percentile, int pointCount)
        {
            SelectionSettings.Percentile(percentile).Validate();
            return (int)Math.Floor((1 - percentile) * pointCount + 0.5 + 1e-9);
        }

        /// <summary>Every policy but Tolerance, which measures placement errors (use the overload with a measure).</summary>
        public static SelectionResult Select(EvaluationGrid grid, float[] scores, SelectionSettings settings)
        {
            if (grid == null) throw new ArgumentNullException(nameof(grid));
            return Select(new ScoredPoints(grid, scores), settings, null);
        }

        /// <param name="points">The grid, its scores and which points are valid, with their rankings cached across calls.
        /// Only valid points are ever selected, by every policy and every completion step.</param>
        /// <param name="measure">The placement error, needed by the Tolerance policy only (may be null otherwise).</param>
        public static SelectionResult Select(ScoredPoints points, SelectionSettings settings, IPlacementErrorMeasure measure)
        {
            if (points == null) throw new ArgumentNullException(nameof(points));
            settings.Validate();
            int n = points.ValidCount;
            var valid = points.Valid;
            switch (settings.Policy)
            {
                case SelectionPolicy.Percentile:
                    return Complete(points.Grid, Prefix(points.ScoreOrder, PercentileCount(settings.Value, n)), settings.KeepBoundsCorners, points.ScoreOrder, valid);
                case SelectionPolicy.Budget:
                    return Complete(points.Grid, Prefix(points.ScoreOrder, (int)Math.Min(settings.Value, n)), settings.KeepBoundsCorners, points.ScoreOrder, valid);
                case SelectionPolicy.Spread:
                    return Complete(points.Grid, Prefix(points.SpreadOrder, (int)Math.Min(settings.Value, n)), settings.KeepBoundsCorners, points.SpreadOrder, valid);
                case SelectionPolicy.Threshold:
                    double[] remapped = ScoreRanking.Remap(points.Scores);
                    var kept = new HashSet<int>();
                    for (int p = 0; p < points.Count; p++)
                        if ((valid == null || valid[p]) && !float.IsNaN(points.Scores[p]) && remapped[p] >= settings.Value) kept.Add(p);
                    return Complete(points.Grid, kept, settings.KeepBoundsCorners, points.ScoreOrder, valid);
                default:
                    if (measure == null) throw MissingMeasure();
                    return WithinTolerance(points.Grid, points.SpreadOrder, settings, measure, valid);
            }
        }

        /// <summary>A policy over a ranking that is not made of scores (the insertion ranking, a reference ordering): Budget
        /// and Spread keep its first K points, Percentile its first PercentileCount(p, N), Tolerance its smallest prefix
        /// within τ (<see cref="WithinTolerance"/>); every selection is completed as usual (bounds corners, tetrahedron).
        /// Threshold needs scores and is refused.</summary>
        /// <param name="measure">The placement error, needed by the Tolerance policy only (may be null otherwise).</param>
        /// <param name="valid">One flag per grid point (null: all valid): invalid points are dropped from the ranking and
        /// never become probes (<see cref="ValidCandidates"/>); the valid ones must span a tetrahedron.</param>
        public static SelectionResult SelectFromRanking(EvaluationGrid grid, int[] ranking, SelectionSettings settings, IPlacementErrorMeasure measure,
            bool[] valid = null)
        {
            if (grid == null) throw new ArgumentNullException(nameof(grid));
            if (ranking == null || ranking.Length != grid.Count)
                throw new SelectionException("need a ranking of all " + grid.Count + " points, got " + (ranking?.Length ?? 0));
            CheckRanking(ranking, grid.Count, null);
            settings.Validate();
            if (valid != null)
            {
                ValidCandidates.Check(grid, valid);
                ranking = ValidCandidates.Filter(ranking, valid); // the valid points in ranking order: nothing else is a candidate
            }
            return FromPrefixes(grid, ranking.Length, count => ranking, settings, measure, valid);
        }

        /// <summary><see cref="SelectFromRanking"/> over a ranking computed only as far as it is read (e.g.
        /// <see cref="Quality.InsertionOrder.Prefix"/>): a budget reads its first K points, the tolerance search the prefixes
        /// it tries, and nothing further is computed. Same selections as over the whole ranking.</summary>
        /// <param name="candidates">The points the whole ranking holds: the grid's, or its valid ones.</param>
        /// <param name="prefix">Returns at least the first min(count, candidates) points of the ranking (more is allowed),
        /// valid grid points each listed once, which span a tetrahedron whatever the count (the tetrahedron guarantee
        /// completes a selection from them only).</param>
        public static SelectionResult SelectFromPrefixes(EvaluationGrid grid, int candidates, RankingPrefix prefix, SelectionSettings settings,
            IPlacementErrorMeasure measure, bool[] valid = null)
        {
            if (grid == null) throw new ArgumentNullException(nameof(grid));
            if (prefix == null) throw new ArgumentNullException(nameof(prefix));
            settings.Validate();
            int expected = valid == null ? grid.Count : ValidCandidates.Check(grid, valid);
            if (candidates != expected)
                throw new SelectionException("the ranking holds " + candidates + " points, but the grid has " + expected + (valid == null ? "" : " valid") + " points");
            return FromPrefixes(grid, candidates, count =>
            {
                int[] head = prefix(count);
                if (head == null || head.Length < Math.Min(count, candidates) || head.Length > candidates)
                    throw new SelectionException("the ranking's prefix for " + count + " points has " + (head?.Length ?? 0) + " (of " + candidates + ")");
                CheckRanking(head, grid.Count, valid);
                return head;
            }, settings, measure, valid);
        }

        private static SelectionResult FromPrefixes(EvaluationGrid grid, int n, RankingPrefix prefix, SelectionSettings settings, IPlacementErrorMeasure measure,
            bool[] valid)
        {
            switch (settings.Policy)
            {
                case SelectionPolicy.Percentile:
                    return Head(grid, prefix, PercentileCount(settings.Value, n), settings.KeepBoundsCorners, valid);
                case SelectionPolicy.Budget:
                case SelectionPolicy.Spread:
                    return Head(grid, prefix, (int)Math.Min(settings.Value, n), settings.KeepBoundsCorners, valid);
                case SelectionPolicy.Threshold:
                    throw new SelectionException("the score threshold policy needs the network's scores, and this ranking has none; " +
                                                 "choose Tolerance, Spread or Budget (a prefix of the ranking), or the Network method");
                default:
                    if (measure == null) throw MissingMeasure();
                    return WithinTolerance(grid, n, prefix, settings, measure, valid);
            }
        }

        /// <summary>The ranking's first <paramref name="count"/> points, completed (the guarantee draws from the prefix read).</summary>
        private static SelectionResult Head(EvaluationGrid grid, RankingPrefix prefix, int count, bool keepBoundsCorners, bool[] valid)
        {
            int[] head = prefix(count);
            return Complete(grid, Prefix(head, count), keepBoundsCorners, head, valid);
        }

        /// <summary>The tolerance policy over any ranking (the spread ranking by default; a reference ordering or a
        /// baseline for comparisons): the smallest prefix, completed like every other selection (bounds corners,
        /// tetrahedron), whose mean error is ≤ τ (<see cref="ToleranceSearch"/>). The error is measured on exactly the
        /// set that is returned.</summary>
        public static SelectionResult WithinTolerance(EvaluationGrid grid, int[] ranking, SelectionSettings settings, IPlacementErrorMeasure measure) =>
            WithinTolerance(grid, ranking, settings, measure, null);

        /// <param name="valid">One flag per grid point (null: all valid); <paramref name="ranking"/> must then rank exactly
        /// the valid points.</param>
        public static SelectionResult WithinTolerance(EvaluationGrid grid, int[] ranking, SelectionSettings settings, IPlacementErrorMeasure measure,
            bool[] valid)
        {
            if (grid == null) throw new ArgumentNullException(nameof(grid));
            int candidates = valid == null ? grid.Count : grid.Count - ValidCandidates.CountInvalid(valid);
            if (ranking == null || ranking.Length != candidates)
                throw new SelectionException("the tolerance search needs a ranking of all " + candidates + (valid == null ? "" : " valid") +
                                             " points, got " + (ranking?.Length ?? 0));
            CheckRanking(ranking, grid.Count, valid);
            if (settings.Policy != SelectionPolicy.Tolerance)
                throw new SelectionException("the tolerance search needs tolerance settings, got the " + settings.Policy + " policy");
            settings.Validate();
            if (measure == null) throw MissingMeasure();
            return WithinTolerance(grid, ranking.Length, count => ranking, settings, measure, valid);
        }

        private static SelectionResult WithinTolerance(EvaluationGrid grid, int n, RankingPrefix prefix, SelectionSettings settings,
            IPlacementErrorMeasure measure, bool[] valid)
        {
            var tried = new Dictionary<int, SelectionResult>();
            var search = ToleranceSearch.Run(n, count =>
            {
                int[] head = prefix(count);
                var selection = Complete(grid, Prefix(head, count), settings.KeepBoundsCorners, head, valid);
                tried[count] = selection;
                return measure.MeanError(selection.Indices);
            }, settings.Value);
            var chosen = tried[search.Count];
            return new SelectionResult(chosen.Indices, chosen.CornersAdded, chosen.AddedForTetrahedron, search);
        }

        private static SelectionException MissingMeasure() =>
            new SelectionException("the tolerance policy measures the placement error against the lighting at every evaluation point; " +
                                   "sample the lighting first (Lighting data step), or choose the Spread policy with a probe count");

        /// <summary>Every point of the ranking is a grid point, valid, and listed once (with the length checked by the
        /// caller, the ranking is then exactly the valid points).</summary>
        private static void CheckRanking(int[] ranking, int pointCount, bool[] valid)
        {
            var seen = new bool[pointCount];
            for (int r = 0; r < ranking.Length; r++)
            {
                int point = ranking[r];
                if ((uint)point >= (uint)pointCount)
                    throw new SelectionException("ranking position " + r + " names point " + point + ", outside the " + pointCount + " points");
                if (valid != null && !valid[point])
                    throw new SelectionException("ranking position " + r + " names point " + point + ", which is inside geometry (invalid) and can never be a probe");
                if (seen[point]) throw new SelectionException("ranking lists point " + point + " twice");
                seen[point] = true;
            }
        }

        private static HashSet<int> Prefix(int[] ranking, int count)
        {
            var selected = new HashSet<int>();
            for (int r = 0; r < count; r++) selected.Add(ranking[r]);
            return selected;
        }

        /// <summary>The options applied after every policy, in the documented order: bounds corners, then the
        /// tetrahedron guarantee (which takes its extra points from <paramref name="ranking"/>, a ranking of valid points).</summary>
        private static SelectionResult Complete(EvaluationGrid grid, HashSet<int> selected, bool keepBoundsCorners, int[] ranking, bool[] valid)
        {
            int corners = keepBoundsCorners ? AddCorners(grid, selected, valid) : 0;
            int added = TetrahedronGuarantee.Ensure(grid, ranking, selected);
            var indices = new int[selected.Count];
            selected.CopyTo(indices);
            Array.Sort(indices);
            return new SelectionResult(indices, corners, added);
        }

        /// <summary>Adds <see cref="BoundsCorners"/> to the selection; returns how many were added.</summary>
        private static int AddCorners(EvaluationGrid grid, ISet<int> selected, bool[] valid)
        {
            int added = 0;
            foreach (int index in BoundsCorners(grid, valid))
                if (selected.Add(index)) added++;
            return added;
        }

        /// <summary>The grid point whose cell holds each box corner (a grid point unless a filter such as "drop points
        /// inside walls" removed it, in which case that corner is skipped; so is a corner inside geometry), each once.</summary>
        internal static List<int> BoundsCorners(EvaluationGrid grid, bool[] valid)
        {
            if (grid.Boxes.Count == 0)
                throw new SelectionException("this grid was rebuilt from stored ids and has no boxes, so the bounds corners are unknown; turn off 'keep bounds corners'");
            var corners = new List<int>();
            foreach (var box in grid.Boxes)
            {
                for (int c = 0; c < 8; c++)
                {
                    var corner = box.Corner(c);
                    int index = LatticeId.TryCellOf(corner, grid.CellSize, out var id) ? grid.IndexOf(id) : -1;
                    if (index >= 0 && (valid == null || valid[index]) && !corners.Contains(index)) corners.Add(index);
                }
            }
            return corners;
        }
    }
}
