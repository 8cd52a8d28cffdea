using System;
using System.Numerics;

namespace Lpnn.Probes.Core.Features
{
    /// <summary>Probe validity: an evaluation point inside geometry must never become a probe (Documentation~/features.md
    /// "Probe validity"; Python: lpnn/core/validity.py). Unity's Adaptive Probe Volumes rule: the share of a point's rays
    /// that hit a back face, invalid above 0.25 (Unity-Technologies/Graphics, SRP Core ProbeDilationSettings.SetDefaults,
    /// dilationValidityThreshold). A ray hits a back face when the surface's oriented normal (the side its winding calls
    /// front) points along the ray; misses count as rays, not as back faces.</summary>
    public static class ProbeValidity
    {
        public const double BackFaceThreshold = 0.25;

        /// <summary>Share of back-face hits among one point's rays.</summary>
        public static double BackFaceFraction(Vector3[] directions, bool[] hits, Vector3[] normals)
        {
            if (directions == null || hits == null || normals == null) throw new ArgumentNullException(directions == null ? nameof(directions) : hits == null ? nameof(hits) : nameof(normals));
            int rays = directions.Length;
            if (rays == 0) throw new ArgumentException("a point needs at least one ray", nameof(directions));
            if (hits.Length != rays || normals.Length != rays)
                throw new ArgumentException("directions (" + rays + "), hits (" + hits.Length + ") and normals (" + normals.Length + ") differ in length");
            int back = 0;
            for (int r = 0; r < rays; r++)
                if (hits[r] && (double)normals[r].X * directions[r].X + (double)normals[r].Y * directions[r].Y + (double)normals[r].Z * directions[r].Z > 0.0)
                    back++;
            return back / (double)rays;
        }

        /// <summary>True when the back-face share exceeds the threshold: the point is inside geometry.</summary>
        public static bool IsInvalid(double backFaceFraction, double threshold = BackFaceThreshold) => backFaceFraction > threshold;
    }
}
