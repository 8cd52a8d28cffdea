using System;
using Lpnn.Probes.Core.Selection;

namespace Lpnn.Probes.Core.Quality
{
    /// <summary>Measures probe sets chosen from one grid: tetrahedralises the probes' positions (Unity's tetrahedraliser in
    /// the editor) and computes their placement error against the grid's reference lighting. The tolerance policy's
    /// measure.</summary>
    public sealed class PlacementEvaluator : IPlacementErrorMeasure
    {
        public ReferenceLighting Reference { get; }
        public ITetrahedralizer Tetrahedralizer { get; }

        public PlacementEvaluator(ReferenceLighting reference, ITetrahedralizer tetrahedralizer)
        {
            Reference = reference ?? throw new ArgumentNullException(nameof(reference));
            Tetrahedralizer = tetrahedralizer ?? throw new ArgumentNullException(nameof(tetrahedralizer));
        }

        /// <param name="probes">Evaluation point indices of the probes.</param>
        public PlacementErrorResult Evaluate(int[] probes) => PlacementError.Evaluate(Reference, probes, TetrahedraOf(probes));

        /// <summary><see cref="Evaluate"/>'s irradiance mean, computed alone (the tolerance search's many evaluations need
        /// no SMAPE or percentile).</summary>
        public double MeanError(int[] probeIndices) => PlacementError.IrradianceMean(Reference, probeIndices, TetrahedraOf(probeIndices));

        /// <summary>The probes' tetrahedra, numbered by the tie rule (the probe indices checked first, so a bad index is named
        /// before the tetrahedraliser sees it).</summary>
        private int[] TetrahedraOf(int[] probes)
        {
            ProbeIndices.Check(probes, Reference.Count);
            return TetrahedronNumbering.Tetrahedralize(Tetrahedralizer, Reference, probes);
        }
    }
}
