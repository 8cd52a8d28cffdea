using System.Numerics;

namespace Lpnn.Probes.Core.Features
{
    /// <summary>A raycaster that can also end each ray at its own distance. The segment test (Documentation~/in-use.md
    /// "Definitions" 2, used by the in-use rule and the leak check) then casts every segment to its own length, so a
    /// segment's answer depends on that segment alone: cast up to the longest segment of its batch instead (all a plain
    /// <see cref="IRaycaster"/> offers), a ray that grazes a triangle in its own plane can be answered by where the longer
    /// ray ends (Embree decides such a ray by its end: 4 of 4.2 million segments of ctf_compromise's leak checks), and
    /// rays run no farther than they must. Python's raycasters offer the same as `first_hit_distances`
    /// (Training~/lpnn/core/segments.py).</summary>
    public interface IPerRayDistanceRaycaster : IRaycaster
    {
        /// <summary>Casts ray n from origins[n] along the unit directions[n], up to maxDistances[n], writing results[n]: its
        /// distance as <see cref="IRaycaster.Cast"/> writes it; its normal may be left zero (the segment test reads only
        /// whether and where a ray hits, and Python's `first_hit_distances` answers distances only).</summary>
        void Cast(Vector3[] origins, Vector3[] directions, float[] maxDistances, RayHit[] results);
    }
}
