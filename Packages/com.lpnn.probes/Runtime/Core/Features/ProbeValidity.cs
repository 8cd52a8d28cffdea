using System;
using System.Numerics;

namespace Lpnn.Probes.Core.Features
{
    /// <summary>Probe validity: an evaluation point inside geometry must never become a probe (Documentation~/features.md
    /// "Probe validity"; Python: lpnn/core/validity.py). Unity's Adaptive Probe Volumes rule: the share of a point's rays
    /// that hit a back face, invalid above 0.25 (Unity-Technologies/Graphics, SRP Core ProbeDilationSettings.SetDefaults,
    /// dilationValidityThreshold). A ray hits a back face when the surface's oriented normal (the side its winding calls
    /// front) points along the ray; misses count as rays, not as back faces.</summary>
    internal static class ProbeValidity
    {
        public const double BackFaceThreshold = 0.25;

        /// <summary>How far the validity rays reach (metres; Python: lpnn.core.validity.RAY_LENGTH): longer than any
        /// level, so a ray that leaves the scene misses, and a point deep inside a thick mesh still meets its back faces.</summary>
        public const float RayLength = 10000f;

        /// <summary>The optional capture section (float32 [N]) holding each point's back-face fraction
        /// (Documentation~/file-formats.md; Python: lpnn.core.validity.CAPTURE_SECTION).</summary>
        public const string CaptureSection = "back_face_fraction";

        /// <summary>The back-face fraction a point inside a solid collider gets (<see cref="InsideColliders"/>): as if the
        /// box, sphere, capsule, convex mesh or terrain were the closed triangle mesh Python's importer sees, every ray
        /// leaving it through a back face. The rays themselves cannot tell: they do not report a collider they start in.</summary>
        public const float InsideColliderFraction = 1f;

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
                if (hits[r] && IsBackFace(normals[r], directions[r])) back++;
            return back / (double)rays;
        }

        /// <summary>Share of back-face hits among the rays of one point whose results start at
        /// <paramref name="offset"/> in <paramref name="hits"/> (one per direction; a miss has infinite distance).</summary>
        public static double BackFaceFraction(Vector3[] directions, RayHit[] hits, int offset)
        {
            if (directions == null || hits == null) throw new ArgumentNullException(directions == null ? nameof(directions) : nameof(hits));
            int rays = directions.Length;
            if (rays == 0) throw new ArgumentException("a point needs at least one ray", nameof(directions));
            if (offset < 0 || offset + rays > hits.Length)
                throw new ArgumentException("the point's " + rays + " rays from " + offset + " do not fit in " + hits.Length + " results");
            int back = 0;
            for (int r = 0; r < rays; r++)
                if (hits[offset + r].IsHit && IsBackFace(hits[offset + r].Normal, directions[r])) back++;
            return back / (double)rays;
        }

        /// <summary>True when the ray meets the surface from behind: its oriented normal points along the ray.</summary>
        public static bool IsBackFace(Vector3 normal, Vector3 direction) =>
            (double)normal.X * direction.X + (double)normal.Y * direction.Y + (double)normal.Z * direction.Z > 0.0;

        /// <summary>True when the back-face share exceeds the threshold: the point is inside geometry.</summary>
        public static bool IsInvalid(double backFaceFraction, double threshold = BackFaceThreshold) => backFaceFraction > threshold;
    }
}
