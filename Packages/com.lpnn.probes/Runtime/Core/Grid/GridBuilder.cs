using System;
using System.Collections.Generic;
using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Core.Grid
{
    /// <summary>Builds evaluation grids (Documentation~/grid.md): the union of boxes on a lattice anchored at
    /// the world origin. The exact point count is known before any per-point array is allocated.</summary>
    public static class GridBuilder
    {
        public const int DefaultPointLimit = 2000000;

        /// <summary>Rows are bounded too, so absurd inputs fail fast instead of enumerating forever.</summary>
        public const int RowsPerPointLimit = 4;

        /// <summary>One run of covered points: row (j, k), i from Start to End inclusive.</summary>
        private struct RowRun : IComparable<RowRun>
        {
            public int J, K, Start, End;

            public int CompareTo(RowRun other)
            {
                if (K != other.K) return K < other.K ? -1 : 1;
                if (J != other.J) return J < other.J ? -1 : 1;
                if (Start != other.Start) return Start < other.Start ? -1 : 1;
                return End.CompareTo(other.End);
            }
        }

        /// <summary>Exact number of grid points for these boxes and cell size (no per-point allocation).
        /// <paramref name="pointLimit"/> only sets the candidate-row bound; the count itself may exceed it.</summary>
        public static long CountPoints(IReadOnlyList<GridBox> boxes, double cellSize, int pointLimit = DefaultPointLimit)
        {
            ValidateInputs(boxes, cellSize, pointLimit);
            var coverages = Coverages(boxes, cellSize);
            CheckRowBound(boxes, cellSize, coverages, pointLimit);
            return Merge(CollectRuns(coverages)).Total;
        }

        /// <summary>Builds the grid, or throws <see cref="GridException"/> naming the problem and the fix.</summary>
        public static EvaluationGrid Build(IReadOnlyList<GridBox> boxes, double cellSize, int pointLimit = DefaultPointLimit)
        {
            ValidateInputs(boxes, cellSize, pointLimit);
            var coverages = Coverages(boxes, cellSize);
            CheckRowBound(boxes, cellSize, coverages, pointLimit);
            var merged = Merge(CollectRuns(coverages));
            if (merged.Total > pointLimit)
            {
                throw new GridException(
                    "the evaluation grid would have " + InvariantFormat.Count(merged.Total) + " points, over the limit of " +
                    InvariantFormat.Count(pointLimit) + ", at cell size " + InvariantFormat.Number(cellSize) + "; " +
                    Advice(SuggestCellSize(boxes, cellSize, coverages, pointLimit, merged.Total)) + " (or shrink the boxes)");
            }
            var ids = new int[merged.Total * 3];
            int n = 0;
            foreach (var run in merged.Runs)
            {
                for (int i = run.Start; i <= run.End; i++, n++)
                {
                    ids[3 * n] = i;
                    ids[3 * n + 1] = run.J;
                    ids[3 * n + 2] = run.K;
                }
            }
            var boxCopy = new GridBox[boxes.Count];
            for (int b = 0; b < boxes.Count; b++) boxCopy[b] = boxes[b];
            return new EvaluationGrid(cellSize, ids, boxCopy);
        }

        /// <summary>The smallest cell size with 3 significant digits at which the grid fits the limits, or null
        /// when it already fits at <paramref name="cellSize"/> or no size within 400 steps up fits.</summary>
        public static double? FittingCellSize(IReadOnlyList<GridBox> boxes, double cellSize, int pointLimit = DefaultPointLimit)
        {
            ValidateInputs(boxes, cellSize, pointLimit);
            var coverages = Coverages(boxes, cellSize);
            bool rowsFit = CandidateRows(coverages) <= (double)pointLimit * RowsPerPointLimit;
            return SuggestCellSize(boxes, cellSize, coverages, pointLimit, rowsFit ? Merge(CollectRuns(coverages)).Total : -1);
        }

        private static string Advice(double? suggestion) =>
            suggestion.HasValue
                ? "a cell size of " + InvariantFormat.Number(suggestion.Value) + " or larger would fit"
                : "use a larger cell size";

        private static void ValidateInputs(IReadOnlyList<GridBox> boxes, double cellSize, int pointLimit)
        {
            if (boxes == null || boxes.Count == 0)
                throw new GridException("the volume has no boxes; add at least one box");
            if (!(cellSize > 0) || double.IsInfinity(cellSize))
                throw new GridException("cell size " + InvariantFormat.Number(cellSize) + " must be a finite number greater than 0");
            if (pointLimit < 1) throw new GridException("point limit " + pointLimit + " must be at least 1");
            for (int b = 0; b < boxes.Count; b++) boxes[b].Validate(b);
        }

        /// <summary>Per-box coverage at this cell size; throws when lattice ids would pass ±2^30.</summary>
        private static BoxCoverage[] Coverages(IReadOnlyList<GridBox> boxes, double cellSize)
        {
            var coverages = new BoxCoverage[boxes.Count];
            for (int b = 0; b < boxes.Count; b++) coverages[b] = new BoxCoverage(boxes[b], cellSize);
            return coverages;
        }

        /// <summary>Candidate rows: the (j, k) ranges of every box, summed (empty rows included).</summary>
        private static double CandidateRows(BoxCoverage[] coverages)
        {
            double rows = 0;
            foreach (var coverage in coverages) rows += coverage.RowCount;
            return rows;
        }

        private static void CheckRowBound(IReadOnlyList<GridBox> boxes, double cellSize, BoxCoverage[] coverages, int pointLimit)
        {
            double rows = CandidateRows(coverages), bound = (double)pointLimit * RowsPerPointLimit;
            if (rows <= bound) return;
            throw new GridException(
                "cell size " + InvariantFormat.Number(cellSize) + " gives " + InvariantFormat.Count((long)Math.Min(rows, long.MaxValue)) +
                " candidate grid rows, more than " + InvariantFormat.Count((long)bound) + " (4 × the point limit " +
                InvariantFormat.Count(pointLimit) + "); " + Advice(SuggestCellSize(boxes, cellSize, coverages, pointLimit)));
        }

        private static List<RowRun> CollectRuns(BoxCoverage[] coverages)
        {
            var runs = new List<RowRun>((int)Math.Min(CandidateRows(coverages), 1 << 20));
            foreach (var coverage in coverages)
            {
                for (long k = coverage.KMin; k <= coverage.KMax; k++)
                {
                    for (long j = coverage.JMin; j <= coverage.JMax; j++)
                    {
                        if (coverage.TryRow(j, k, out long start, out long end))
                            runs.Add(new RowRun { J = (int)j, K = (int)k, Start = (int)start, End = (int)end });
                    }
                }
            }
            return runs;
        }

        private struct MergedRuns
        {
            public List<RowRun> Runs;
            public long Total;
        }

        /// <summary>Sorts runs into grid order and merges overlapping or adjacent runs of the same row.</summary>
        private static MergedRuns Merge(List<RowRun> runs)
        {
            runs.Sort();
            var merged = new List<RowRun>(runs.Count);
            long total = 0;
            foreach (var run in runs)
            {
                int last = merged.Count - 1;
                if (last >= 0 && merged[last].J == run.J && merged[last].K == run.K && (long)run.Start <= (long)merged[last].End + 1)
                {
                    var grown = merged[last];
                    if (run.End > grown.End)
                    {
                        total += run.End - grown.End;
                        grown.End = run.End;
                        merged[last] = grown;
                    }
                    continue;
                }
                merged.Add(run);
                total += (long)run.End - run.Start + 1;
            }
            return new MergedRuns { Runs = merged, Total = total };
        }

        private const int FittingSteps = 400;

        /// <summary>grid.md "Limits": the search starts from h·∛(count/limit). When even the rows are over their
        /// bound, the cell first grows until they fit (rows scale as 1/h²) and the count there is the cheap
        /// candidate-point upper bound (exact for one axis-aligned box), so no huge grid is ever enumerated.</summary>
        private static double? SuggestCellSize(IReadOnlyList<GridBox> boxes, double cellSize, BoxCoverage[] coverages, int pointLimit,
            long exactCount = -1)
        {
            double countedAt = cellSize, bound = (double)pointLimit * RowsPerPointLimit;
            double rows = CandidateRows(coverages);
            for (int step = 0; step < FittingSteps && rows > bound; step++)
            {
                countedAt = InvariantFormat.RoundUpSignificant(countedAt * Math.Max(Math.Sqrt(rows / bound), 1.001), 3);
                try
                {
                    coverages = Coverages(boxes, countedAt);
                }
                catch (GridException)
                {
                    return null;
                }
                rows = CandidateRows(coverages);
            }
            if (rows > bound) return null;
            double count = countedAt == cellSize && exactCount >= 0 ? exactCount : CandidatePoints(coverages);
            if (count <= pointLimit)
                return countedAt == cellSize ? (double?)null : FromEstimate(boxes, cellSize, countedAt, pointLimit);
            return FromEstimate(boxes, cellSize, countedAt * Math.Pow(count / pointLimit, 1.0 / 3.0), pointLimit);
        }

        /// <summary>Σ over boxes of the lattice points in the box's range: an upper bound of the grid's count.</summary>
        private static double CandidatePoints(BoxCoverage[] coverages)
        {
            double points = 0;
            foreach (var c in coverages)
                points += c.IMax < c.IMin ? 0 : c.RowCount * (c.IMax - c.IMin + 1);
            return points;
        }

        /// <summary>From the estimate rounded up to 3 digits, one third-digit unit up until the grid fits, then down
        /// while it still fits (staying above the original cell size); null when 400 steps up never fit.</summary>
        private static double? FromEstimate(IReadOnlyList<GridBox> boxes, double cellSize, double estimate, int pointLimit)
        {
            double candidate = InvariantFormat.RoundUpSignificant(estimate, 3);
            int step = 0;
            for (; step < FittingSteps && !Fits(boxes, candidate, pointLimit); step++)
                candidate = InvariantFormat.RoundUpSignificant(candidate + ThirdDigit(candidate), 3);
            if (step == FittingSteps && !Fits(boxes, candidate, pointLimit)) return null;
            for (step = 0; step < FittingSteps; step++)
            {
                double lower = InvariantFormat.RoundUpSignificant(candidate - ThirdDigit(candidate * (1 - 1e-12)), 3);
                if (!(lower < candidate) || lower <= cellSize || !Fits(boxes, lower, pointLimit)) break;
                candidate = lower;
            }
            return candidate;
        }

        /// <summary>One unit of the third significant digit of a positive value (0.01 for 1.23).</summary>
        private static double ThirdDigit(double value) => Math.Pow(10, Math.Floor(Math.Log10(value)) - 2);

        /// <summary>Whether this cell size passes every limit (ids, rows, points).</summary>
        private static bool Fits(IReadOnlyList<GridBox> boxes, double cellSize, int pointLimit)
        {
            try
            {
                var coverages = Coverages(boxes, cellSize);
                return CandidateRows(coverages) <= (double)pointLimit * RowsPerPointLimit &&
                       Merge(CollectRuns(coverages)).Total <= pointLimit;
            }
            catch (GridException)
            {
                return false;
            }
        }
    }
}
