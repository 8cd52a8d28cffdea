using System.Runtime.CompilerServices;
using Lpnn.Probes.Core;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Quality;
using Lpnn.Probes.Core.Selection;

namespace Lpnn.Probes.Editor
{
    /// <summary>What placement reuses between inspector repaints, held as long as the arrays it was made from: the
    /// rankings of a set of scores (the spread ranking is O(N log N)) and the reference lighting of a set of SH (42
    /// values per point). Keyed by array identity — a new Lighting or Scoring result is a new array, so nothing stale
    /// is ever returned — and weakly, so they go when the session drops the arrays.</summary>
    public static class PlacementInputs
    {
        private static readonly ConditionalWeakTable<float[], ScoredPoints> Rankings = new ConditionalWeakTable<float[], ScoredPoints>();
        private static readonly ConditionalWeakTable<float[], ReferenceLighting> References = new ConditionalWeakTable<float[], ReferenceLighting>();

        /// <summary>The grid's stored scores and valid points with their rankings (computed on first use, then kept; the
        /// record replaces its validity flags together with its scores, so the scores' identity is the key).</summary>
        public static ScoredPoints Scored(EvaluationGrid grid, LpnnScoreRecord record)
        {
            var scores = record.Scores;
            if (Rankings.TryGetValue(scores, out var points) && points.Grid == grid) return points;
            Rankings.Remove(scores);
            points = new ScoredPoints(grid, scores, record.Valid);
            Rankings.Add(scores, points);
            return points;
        }

        /// <summary>The lighting the placement error compares against: the Lighting step's SH at the session's grid.</summary>
        public static ReferenceLighting Reference(LpnnSession session, EvaluationGrid grid)
        {
            if (session.Sh == null || session.Grid != grid)
                throw new LpnnException("the placement error compares against the lighting at every evaluation point, and there is none for this " +
                                        "grid (a script reload or a grid change drops it): run the Lighting data step");
            return References.GetValue(session.Sh, sh => ReferenceLighting.FromGrid(grid, sh));
        }

        /// <summary>Measures probe sets of this grid with Unity's tetrahedralisation.</summary>
        public static PlacementEvaluator Evaluator(LpnnSession session, EvaluationGrid grid) =>
            new PlacementEvaluator(Reference(session, grid), new UnityTetrahedralizer());
    }
}
