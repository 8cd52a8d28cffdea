namespace Lpnn.Probes.Core.Quality
{
    /// <summary>How one evaluation point is interpolated: up to 4 probes (indices into the probe list) and their
    /// weights (≥ 0, sum 1). Inside the hull the containing tetrahedron; outside, the 3 corners of the hull triangle
    /// holding the nearest hull point (the fourth weight is 0).</summary>
    public struct Stencil
    {
        public int Probe0, Probe1, Probe2, Probe3;
        public double Weight0, Weight1, Weight2, Weight3;
        /// <summary>True when the point is outside the probes' hull and takes the weights of its nearest hull point.</summary>
        public bool Outside;
        /// <summary>The tetrahedron holding the point, or (outside) the one owning its nearest hull triangle: an index into
        /// the mesh's checked tetrahedra, so points interpolated from the same cell share it.</summary>
        public int Cell;
    }
}
