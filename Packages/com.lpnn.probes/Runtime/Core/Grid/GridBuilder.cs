using System;
using System.Collections.Generic;
using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Core.Grid
{
    /// <summary>Builds evaluation grids (Documentation~/grid.md): the union of boxes on a lattice anchored at
    /// the world origin. The exact point count is known before any per-point array is allocated.</summary>
    public static class GridBuilder
    {
        public const int DefaultPointLimit = 2_000_000;

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

        /// <summary>Exact number of grid points for these boxes and cell size (no per-point allocation).</summary>
        public static long CountPoints(IReadOnlyList<GridBox> boxes, double cellSize, int pointLimit = DefaultPointLimit)
        {
            return Merge(CollectRuns(boxes, cellSize, pointLimit)).Total;
        }

        /// <summary>Builds the grid, or throws <see cref="GridException"/> naming the problem and the fix.</summary>
        public static EvaluationGrid Build(IReadOnlyList<GridBox> boxes, double cellSize, int pointLimit = DefaultPointLimit)
        {
            if (pointLimit < 1) throw new GridException("point limit " + pointLimit + " must be at least 1");
            var merged = Merge(CollectRuns(boxes, cellSize, pointLimit));
            if (merged.Total > pointLimit)
            {
                throw new GridException(
                    "the evaluation grid would have " + InvariantFormat.Count(merged.Total) + " points, over the limit of " +
                    InvariantFormat.Count(pointLimit) + ", at cell size " + InvariantFormat.Number(cellSize) +
                    "; a cell size of " + InvariantFormat.Number(FittingCellSize(boxes, cellSize, merged.Total, pointLimit)) +
                    " or larger would fit (or shrink the boxes)");
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

        private static void ValidateInputs(IReadOnlyList<GridBox> boxes, double cellSize)
        {
            if (boxes == null || boxes.Count == 0)
                throw new GridException("the volume has no boxes; add at least one box");
            if (!(cellSize > 0) || double.IsInfinity(cellSize))
                throw new GridException("cell size " + InvariantFormat.Number(cellSize) + " must be a finite number greater than 0");
            for (int b = 0; b < boxes.Count; b++) boxes[b].Validate(b);
        }

        private static List<RowRun> CollectRuns(IReadOnlyList<GridBox> boxes, double cellSize, int pointLimit)
        {
            ValidateInputs(boxes, cellSize);
            var coverages = new BoxCoverage[boxes.Count];
            double rows = 0;
            for (int b = 0; b < boxes.Count; b++)
            {
                coverages[b] = new BoxCoverage(boxes[b], cellSize);
                rows += coverages[b].RowCount;
            }
            double rowLimit = (double)pointLimit * RowsPerPointLimit;
            if (rows > rowLimit)
            {
                throw new GridException(
                    "the boxes span " + InvariantFormat.Count((long)Math.Min(rows, long.MaxValue)) + " grid rows at cell size " +
                    InvariantFormat.Number(cellSize) + " (limit " + InvariantFormat.Count((long)rowLimit) +
                    "): the grid would be far over the point limit; use a larger cell size");
            }
            var runs = new List<RowRun>((int)Math.Min(rows, 1 << 20));
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

        /// <summary>The smallest cell size with 3 significant digits whose grid fits, found from the h·∛(count/limit)
        /// estimate by stepping one unit of the third digit up (until it fits) or down (while it still fits).</summary>
        private static double FittingCellSize(IReadOnlyList<GridBox> boxes, double cellSize, long count, int pointLimit)
        {
            double candidate = InvariantFormat.RoundUpSignificant(cellSize * Math.Pow((double)count / pointLimit, 1.0 / 3.0), 3);
            const int MaxSteps = 400;
            for (int step = 0; step < MaxSteps && !CountWithin(boxes, candidate, pointLimit); step++)
                candidate = InvariantFormat.RoundUpSignificant(candidate + ThirdDigit(candidate), 3);
            for (int step = 0; step < MaxSteps; step++)
            {
                double lower = InvariantFormat.RoundUpSignificant(candidate - ThirdDigit(candidate * (1 - 1e-12)), 3);
                if (!(lower < candidate) || lower <= cellSize || !CountWithin(boxes, lower, pointLimit)) break;
                candidate = lower;
            }
            return candidate;
        }

        /// <summary>One unit of the third significant digit of a positive value (0.01 for 1.23).</summary>
        private static double ThirdDigit(double value) => Math.Pow(10, Math.Floor(Math.Log10(value)) - 2);

        private static bool CountWithin(IReadOnlyList<GridBox> boxes, double cellSize, int pointLimit)
        {
            try
            {
                return CountPoints(boxes, cellSize, pointLimit) <= pointLimit;
            }
            catch (GridException)
            {
                return false; // still too many rows at this size
            }
        }
    }
}
