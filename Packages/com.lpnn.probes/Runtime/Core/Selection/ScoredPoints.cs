using System;
using Lpnn.Probes.Core.Grid;

namespace Lpnn.Probes.Core.Selection
{
    /// <summary>A grid with one score per point and its two rankings, each computed on first use and kept: the spread
    /// ranking costs O(N log N), and the inspector's live preview re-selects on every slider step.</summary>
    public sealed class ScoredPoints
    {
        private int[] _scoreOrder;
        private int[] _spreadOrder;

        public EvaluationGrid Grid { get; }
        public float[] Scores { get; }
        public int Count => Grid.Count;

        public ScoredPoints(EvaluationGrid grid, float[] scores)
        {
            Grid = grid ?? throw new ArgumentNullException(nameof(grid));
            if (scores == null || scores.Length != grid.Count)
                throw new SelectionException("need one score per evaluation point: got " + (scores?.Length ?? 0) + " scores for " + grid.Count + " points");
            Scores = scores;
        }

        /// <summary>Points by raw score, best first (<see cref="ScoreRanking.Rank"/>).</summary>
        public int[] ScoreOrder => _scoreOrder ?? (_scoreOrder = ScoreRanking.Rank(Scores));

        /// <summary>All points in spread order (<see cref="SpreadRanking"/>).</summary>
        public int[] SpreadOrder => _spreadOrder ?? (_spreadOrder = SpreadRanking.Rank(Grid, Scores));
    }
}
