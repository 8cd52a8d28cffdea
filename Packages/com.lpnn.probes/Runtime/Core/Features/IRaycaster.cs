using System.Numerics;

namespace Lpnn.Probes.Core.Features
{
    /// <summary>The first surface a ray meets. <see cref="Distance"/> is +∞ when nothing is hit within the
    /// maximum distance; <see cref="Normal"/> may face either way (the extractor re-orients it).</summary>
    public struct RayHit
    {
        public float Distance;
        public Vector3 Normal;

        public bool IsHit => !float.IsPositiveInfinity(Distance);

        public static RayHit Miss => new RayHit { Distance = float.PositiveInfinity, Normal = Vector3.Zero };
    }

    /// <summary>Batched ray casts against scene geometry, hitting surfaces of either facing
    /// (Unity: RaycastCommand with hitBackfaces; headless: Embree; tests: exact analytic boxes). A raycaster that can end
    /// each ray at its own distance also implements <see cref="IPerRayDistanceRaycaster"/>, which the segment test uses.</summary>
    public interface IRaycaster
    {
        /// <summary>Casts ray n from origins[n] along the unit directions[n], up to <paramref name="maxDistance"/>,
        /// writing results[n].</summary>
        void Cast(Vector3[] origins, Vector3[] directions, float maxDistance, RayHit[] results);
    }
}
