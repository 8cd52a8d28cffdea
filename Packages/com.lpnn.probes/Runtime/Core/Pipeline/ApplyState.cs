using System;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Quality;

namespace Lpnn.Probes.Core.Pipeline
{
    /// <summary>What the Apply steps publish between them, standing in for the editor's session (LpnnSession: the grid's
    /// lighting and features) and for what PlacementInputs keeps for them (the reference lighting and the insertion order,
    /// computed as far as it was read, reused by later placements while the lighting and features are the same). A step
    /// publishes only when it completed (<see cref="ApplySteps.Rehearse"/>), so a cancelled step leaves the previous state;
    /// the kept insertion order is advanced in whole rounds only (InsertionOrder.Prefix checks cancel before a round), so a
    /// cancelled placement leaves it consistent and the next placement continues from it.</summary>
    internal sealed class ApplyState
    {
        private InsertionOrder _order;
        private ReferenceLighting _reference;

        public EvaluationGrid Grid { get; private set; }
        /// <summary>27 floats per grid point; null before the Lighting step.</summary>
        public float[] Sh { get; private set; }
        /// <summary>The Features step's result for <see cref="Sh"/>; null before it (every point is then a candidate).</summary>
        public FeatureSet Features { get; private set; }

        /// <summary>The insertion order kept for the current lighting and features (null: none computed yet).</summary>
        public InsertionOrder KeptOrder => _order;

        /// <summary>The reference lighting of the current SH (computed once per lighting, as PlacementInputs.Reference).</summary>
        public ReferenceLighting Reference => _reference ?? (_reference = ReferenceLighting.FromGrid(Grid, Sh));

        /// <summary>A new lighting (LpnnSession.SetLighting): the features and the kept order were of the old one.</summary>
        public void PublishLighting(EvaluationGrid grid, float[] sh)
        {
            Grid = grid ?? throw new ArgumentNullException(nameof(grid));
            Sh = sh ?? throw new ArgumentNullException(nameof(sh));
            Features = null;
            _reference = null;
            _order = null;
        }

        /// <summary>New features (LpnnSession.SetFeatures): new valid points, so a new order (PlacementInputs keys it by them).</summary>
        public void PublishFeatures(FeatureSet features)
        {
            if (Sh == null) throw new InvalidOperationException("features before lighting");
            Features = features;
            _order = null;
        }

        /// <summary>The kept insertion order of the valid points, made on first use (PlacementInputs.InsertionOrder).</summary>
        public InsertionOrder InsertionOrder(ITetrahedralizer tetrahedralizer)
        {
            if (_order != null) return _order;
            _order = Quality.InsertionOrder.OfValid(Grid, Sh, Reference.SceneScale, ApplySteps.ValidPoints(Features), tetrahedralizer);
            return _order;
        }
    }
}
