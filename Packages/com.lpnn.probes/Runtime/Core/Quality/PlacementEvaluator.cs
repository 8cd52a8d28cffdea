using System;
using System.Numerics;
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
        public PlacementErrorResult Evaluate(int[] probes)
        {
            ProbeIndices.Check(probes, Reference.Count);
            var positions = new Vector3[probes.Length];
            for (int k = 0; k < probes.Length; k++) positions[k] = Reference.GetPosition(probes[k]);
            int[] tetrahedra = Tetrahedralizer.Tetrahedralize(positions);
            return PlacementError.Evaluate(Reference, probes, tetrahedra);
        }

        public double MeanError(int[] probeIndices) => Evaluate(probeIndices).Irradiance.Mean;
    }
}
