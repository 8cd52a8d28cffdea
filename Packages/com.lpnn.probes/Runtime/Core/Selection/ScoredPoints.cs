using System;
using Lpnn.Probes.Core.Grid;

namespace Lpnn.Probes.Core.Selection
{
    /// <summary>A grid with one score per point, which of its points may become probes (<see cref="ValidCandidates"/>),
    /// and its two rankings over those points, each computed on first use and kept: the spread ranking costs
    /// O(N log N), and the inspector's live preview re-selects on every slider step.</summary>
    public sealed class ScoredPoints
    {
        private int[] _scoreOrder;
        private int[] _spreadOrder;

        public EvaluationGrid Grid { get; }
        public float[] Scores { get; }
        public int Count => Grid.Count;

        /// <summary>One flag per point, false for a point inside geometry; null when every point is valid.</summary>
        public bool[] Valid { get; }

        /// <summary>How many points may become probes.</summary>
        public int ValidCount { get; }

        /// <summary>Every point may become a probe.</summary>
        public ScoredPoints(EvaluationGrid grid, float[] scores) : this(grid, scores, null) { }

        /// <param name="valid">One flag per point (null: all valid); the valid points must span a tetrahedron.</param>
        public ScoredPoints(EvaluationGrid grid, float[] scores, bool[] valid)
        {
            Grid = grid ?? throw new ArgumentNullException(nameof(grid));
            if (scores == null || scores.Length != grid.Count)
                throw new SelectionException("need one score per evaluation point: got " + (scores?.Length ?? 0) + " scores for " + grid.Count + " points");
            Scores = scores;
            Valid = valid;
            ValidCount = valid == null ? grid.Count : ValidCandidates.Check(grid, valid);
        }

        /// <summary>Valid points by raw score, best first (<see cref="ScoreRanking.Rank"/>).</summary>
        public int[] ScoreOrder => _scoreOrder ?? (_scoreOrder = ValidCandidates.Filter(ScoreRanking.Rank(Scores), Valid));

        /// <summary>The valid points in spread order (<see cref="SpreadRanking"/> over the valid points alone, so an
        /// invalid point neither becomes a probe nor pushes its neighbours down the order).</summary>
        public int[] SpreadOrder => _spreadOrder ?? (_spreadOrder = RankSpread());

        private int[] RankSpread()
        {
            if (Valid == null) return SpreadRanking.Rank(Grid, Scores);
            var index = new int[ValidCount];
            var positions = new float[3 * ValidCount];
            var scores = new float[ValidCount];
            for (int n = 0, m = 0; n < Count; n++)
            {
                if (!Valid[n]) continue;
                var p = Grid.GetPosition(n);
                positions[3 * m] = p.X;
                positions[3 * m + 1] = p.Y;
                positions[3 * m + 2] = p.Z;
                scores[m] = Scores[n];
                index[m++] = n;
            }
            int[] order = SpreadRanking.Rank(positions, scores, int.MaxValue);
            for (int r = 0; r < order.Length; r++) order[r] = index[order[r]];
            return order;
        }
    }
}
