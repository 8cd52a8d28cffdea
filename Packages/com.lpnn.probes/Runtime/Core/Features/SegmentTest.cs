using System;
using System.Numerics;

namespace Lpnn.Probes.Core.Features
{
    /// <summary>Whether straight segments cross geometry (Documentation~/in-use.md "Definitions" 2; leaks.md uses the same
    /// test): the segment from a to b is free when a ray from a towards b meets no surface of either facing within their
    /// distance; a zero-length segment is free. <see cref="IRaycaster"/> takes one maximum distance per call, so every
    /// segment is cast up to the longest one and a hit counts only when it is not beyond its own segment's end.</summary>
    internal static class SegmentTest
    {
        public static bool[] Free(IRaycaster raycaster, Vector3[] starts, Vector3[] ends)
        {
            if (raycaster == null) throw new ArgumentNullException(nameof(raycaster));
            if (starts == null) throw new ArgumentNullException(nameof(starts));
            if (ends == null) throw new ArgumentNullException(nameof(ends));
            if (starts.Length != ends.Length)
                throw new ArgumentException("segment starts (" + starts.Length + ") and ends (" + ends.Length + ") differ in length");
            var free = new bool[starts.Length];
            var lengths = new double[starts.Length];
            int cast = 0;
            double longest = 0;
            for (int s = 0; s < starts.Length; s++)
            {
                double dx = (double)ends[s].X - starts[s].X, dy = (double)ends[s].Y - starts[s].Y, dz = (double)ends[s].Z - starts[s].Z;
                lengths[s] = Math.Sqrt(dx * dx + dy * dy + dz * dz);
                free[s] = true;
                if (lengths[s] > 0) { cast++; longest = Math.Max(longest, lengths[s]); }
            }
            if (cast == 0) return free;
            // Zero-length segments have nothing to cross and no direction to cast along.
            var rows = new int[cast];
            var origins = new Vector3[cast];
            var directions = new Vector3[cast];
            for (int s = 0, r = 0; s < starts.Length; s++)
            {
                if (!(lengths[s] > 0)) continue;
                double inverse = 1.0 / lengths[s];
                rows[r] = s;
                origins[r] = starts[s];
                directions[r] = new Vector3((float)(((double)ends[s].X - starts[s].X) * inverse), (float)(((double)ends[s].Y - starts[s].Y) * inverse),
                    (float)(((double)ends[s].Z - starts[s].Z) * inverse));
                r++;
            }
            var hits = new RayHit[cast];
            raycaster.Cast(origins, directions, (float)longest, hits);
            for (int r = 0; r < cast; r++) free[rows[r]] = !(hits[r].Distance <= lengths[rows[r]]);
            return free;
        }
    }
}
