using System;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Selection;

namespace Lpnn.Probes.Core.Quality
{
    /// <summary>"As few probes as the scene requires" (Documentation~/quality.md §4, selection.md): the smallest prefix
    /// of a ranking — the spread ranking of the scores by default — whose mean irradiance error is ≤ τ, measured with
    /// the given tetrahedraliser on exactly the set returned (bounds corners and the tetrahedron guarantee included).</summary>
    public static class TolerancePolicy
    {
        /// <summary>Over the spread ranking of <paramref name="scores"/>.</summary>
        public static SelectionResult Place(EvaluationGrid grid, float[] scores, ReferenceLighting reference, ITetrahedralizer tetrahedralizer,
            double tolerance, bool keepBoundsCorners = false)
        {
            var points = new ScoredPoints(grid, scores);
            return Place(grid, points.SpreadOrder, reference, tetrahedralizer, tolerance, keepBoundsCorners);
        }

        /// <summary>Over any ranking of all grid points (a reference ordering, a baseline).</summary>
        public static SelectionResult Place(EvaluationGrid grid, int[] ranking, ReferenceLighting reference, ITetrahedralizer tetrahedralizer,
            double tolerance, bool keepBoundsCorners = false)
        {
            if (grid == null) throw new ArgumentNullException(nameof(grid));
            if (reference == null) throw new ArgumentNullException(nameof(reference));
            if (reference.Count != grid.Count)
                throw new PlacementErrorException("the reference lighting has " + reference.Count + " points but the grid has " + grid.Count +
                                                  "; sample the lighting for this grid");
            var evaluator = new PlacementEvaluator(reference, tetrahedralizer);
            return ProbeSelector.WithinTolerance(grid, ranking, SelectionSettings.Tolerance(tolerance, keepBoundsCorners), evaluator);
        }
    }
}
