using System.Collections.Generic;

namespace Lpnn.Probes.Core.Quality
{
    /// <summary>The points an interpolation visited and their stencils, in the order it visited them (its in-order
    /// <see cref="PlacementError.StencilVisitor"/>): what a leak check reads after an interpolation — the leak test of a
    /// placement (<see cref="LeakCheck.Find"/>), the leak repair, the leak report and the refinement's leak weighting.</summary>
    internal sealed class StencilLog
    {
        private readonly List<int> points;
        private readonly List<Stencil> stencils;

        /// <param name="capacity">The points expected (0: unknown); only sizes the lists.</param>
        public StencilLog(int capacity = 0)
        {
            points = new List<int>(capacity);
            stencils = new List<Stencil>(capacity);
        }

        /// <summary>Evaluation point indices, in the order visited.</summary>
        public IReadOnlyList<int> Points => points;

        /// <summary>Their stencils, the same order (probe-list indices).</summary>
        public IReadOnlyList<Stencil> Stencils => stencils;

        public int Count => points.Count;

        /// <summary>The visitor to hand an interpolation.</summary>
        public PlacementError.StencilVisitor Visitor => Add;

        private void Add(int point, ref Stencil stencil)
        {
            points.Add(point);
            stencils.Add(stencil);
        }
    }
}
