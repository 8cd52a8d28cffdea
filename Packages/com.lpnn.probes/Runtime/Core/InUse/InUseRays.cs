using System;
using System.Numerics;
using System.Runtime.InteropServices;
using System.Threading;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Core.InUse
{
    /// <summary>The two kinds of ray of the in-use rule (Documentation~/in-use.md "Definitions" 1 and 2), cast in batches
    /// with progress and cancel: floor rays (straight down, at most H) and segment rays (is the segment free?).
    /// Positions are doubles (every comparison is in double); the raycaster gets them as its float Vector3.</summary>
    internal static class InUseRays
    {
        /// <summary>Rays per raycaster call: progress and cancel between calls, ~2 MB of rays and hits at a time.</summary>
        public const int RaysPerBatch = 65536;

        private static readonly Vector3 Down = new Vector3(0, -1, 0);

        /// <summary>f = y − d of each origin's floor ray where it hits, within H, a surface with |n_y| ≥ cos θ; NaN
        /// elsewhere (no walkable floor within the band).</summary>
        public static double[] FloorHeights(Double3[] origins, IRaycaster raycaster, InUseParameters parameters, string stage,
            ProgressCallback progress, CancellationToken cancel) =>
            FloorHeights(origins, raycaster, parameters, stage, 0, origins.Length, progress, cancel);

        /// <summary>As above, reporting progress as rays <paramref name="doneBefore"/> + done of <paramref name="stageTotal"/>
        /// (a stage cast over several calls).</summary>
        public static double[] FloorHeights(Double3[] origins, IRaycaster raycaster, InUseParameters parameters, string stage,
            long doneBefore, long stageTotal, ProgressCallback progress, CancellationToken cancel)
        {
            var heights = new double[origins.Length];
            double band = parameters.BandHeight, walkable = parameters.WalkableCosine;
            CastInBatches(origins, null, Down, AtLeast(band), null, raycaster, stage, doneBefore, stageTotal, progress, cancel,
                (ray, hit) =>
                {
                    double d = Checked(hit, ray);
                    var normal = Double3.FromVector3(hit.Normal);
                    double length = normal.Length;
                    // The raycaster's normals are unit by contract; dividing keeps a slightly unnormalised mesh normal honest.
                    bool isFloor = d <= band && length > 0 && Math.Abs(normal.Y) / length >= walkable;
                    heights[ray] = isFloor ? origins[ray].Y - d : double.NaN;
                });
            return heights;
        }

        /// <summary>Whether nothing is hit on the segment from each start to its end (a zero-length segment is free, and not
        /// cast). A raycaster that can end each ray at its own distance (<see cref="IPerRayDistanceRaycaster"/>) casts each
        /// segment to its own length, so its answer depends on that segment alone (a ray grazing a triangle in its own plane
        /// may be decided by where the ray ends). A plain one casts each batch as far as its longest segment; a hit counts
        /// when within its own segment's length, the same first hit a ray limited to that length finds but for such grazing
        /// rays. Either way a hit counts only within the segment's length in double.</summary>
        public static bool[] SegmentsFree(Double3[] starts, Double3[] ends, IRaycaster raycaster, string stage,
            ProgressCallback progress, CancellationToken cancel)
        {
            if (starts.Length != ends.Length) throw new ArgumentException("segment starts and ends differ in count", nameof(ends));
            var free = new bool[starts.Length];
            int cast = 0;
            for (int s = 0; s < starts.Length; s++)
            {
                free[s] = true;
                if ((ends[s] - starts[s]).LengthSquared > 0) cast++;
            }
            var rays = new int[cast];
            var origins = new Double3[cast];
            var directions = new Double3[cast];
            var lengths = new double[cast];
            double longest = 0;
            int r = 0;
            for (int s = 0; s < starts.Length; s++)
            {
                var offset = ends[s] - starts[s];
                if (!(offset.LengthSquared > 0)) continue;
                rays[r] = s;
                origins[r] = starts[s];
                lengths[r] = offset.Length;
                directions[r] = offset * (1 / lengths[r]);
                longest = Math.Max(longest, lengths[r]);
                r++;
            }
            if (cast == 0) return free;
            double[] ownEnds = raycaster is IPerRayDistanceRaycaster ? lengths : null;
            CastInBatches(origins, directions, Vector3.Zero, AtLeast(longest), ownEnds, raycaster, stage, 0, cast, progress, cancel,
                (ray, hit) => free[rays[ray]] = !(Checked(hit, ray) <= lengths[ray]));
            return free;
        }

        /// <summary>Casts origins[n] along directions[n] (or along <paramref name="direction"/> when directions is null) in
        /// batches, handing each hit to <paramref name="read"/> with its ray index. Each ray ends at
        /// <paramref name="maxDistance"/>, or, given <paramref name="ownEnds"/> (the raycaster then must be an
        /// <see cref="IPerRayDistanceRaycaster"/>), ray n at ownEnds[n] rounded up to a float.</summary>
        private static void CastInBatches(Double3[] origins, Double3[] directions, Vector3 direction, float maxDistance, double[] ownEnds,
            IRaycaster raycaster, string stage, long doneBefore, long stageTotal, ProgressCallback progress, CancellationToken cancel,
            Action<int, RayHit> read)
        {
            if (raycaster == null) throw new ArgumentNullException(nameof(raycaster));
            var perRay = ownEnds == null ? null : (IPerRayDistanceRaycaster)raycaster;
            int batch = Math.Min(RaysPerBatch, origins.Length);
            var rayOrigins = new Vector3[batch];
            var rayDirections = new Vector3[batch];
            var rayEnds = perRay == null ? null : new float[batch];
            var hits = new RayHit[batch];
            for (int first = 0; first < origins.Length; first += batch)
            {
                cancel.ThrowIfCancellationRequested();
                progress?.Invoke(stage, doneBefore + first, stageTotal);
                int count = Math.Min(batch, origins.Length - first);
                if (count != rayOrigins.Length)
                {
                    rayOrigins = new Vector3[count];
                    rayDirections = new Vector3[count];
                    if (perRay != null) rayEnds = new float[count];
                    hits = new RayHit[count];
                }
                for (int r = 0; r < count; r++)
                {
                    rayOrigins[r] = ToVector3(origins[first + r]);
                    rayDirections[r] = directions == null ? direction : ToVector3(directions[first + r]);
                    if (perRay != null) rayEnds[r] = AtLeast(ownEnds[first + r]);
                    hits[r] = RayHit.Miss;
                }
                if (perRay != null) perRay.Cast(rayOrigins, rayDirections, rayEnds, hits);
                else raycaster.Cast(rayOrigins, rayDirections, maxDistance, hits);
                for (int r = 0; r < count; r++) read(first + r, hits[r]);
            }
            progress?.Invoke(stage, doneBefore + origins.Length, stageTotal);
        }

        private static Vector3 ToVector3(Double3 v) => new Vector3((float)v.X, (float)v.Y, (float)v.Z);

        /// <summary>The smallest float maximum distance not below <paramref name="distance"/> (≥ 0): the raycaster takes a
        /// float, and a maximum rounded down would drop a hit the double comparison afterwards counts. The next float up,
        /// as Python's raycaster rounds a ray's end (np.nextafter, Training~/lpnn/scenes/raycast.py), so a ray handed to
        /// Embree from either language ends at the same float (Embree decides a ray grazing a triangle by its end).</summary>
        private static float AtLeast(double distance)
        {
            float rounded = (float)distance;
            if (rounded >= distance) return rounded;
            var next = new FloatBits { Value = rounded };
            next.Bits += rounded >= 0 ? 1 : -1;  // one unit in the last place toward +∞
            return next.Value;
        }

        /// <summary>A float's IEEE 754 bits (BitConverter.SingleToInt32Bits is missing from .NET Framework 4.x, one of Unity's API
        /// compatibility levels).</summary>
        [StructLayout(LayoutKind.Explicit)]
        private struct FloatBits
        {
            [FieldOffset(0)] public float Value;
            [FieldOffset(0)] public int Bits;
        }

        private static double Checked(RayHit hit, int ray)
        {
            double d = hit.Distance;
            if (double.IsNaN(d) || d < 0)
                throw new InUseException("the raycaster returned distance " + InvariantFormat.Number(hit.Distance) + " for ray " + ray +
                                         "; distances must be ≥ 0, or +∞ for no hit (a raycaster bug)");
            if (!Double3.FromVector3(hit.Normal).IsFinite)
                throw new InUseException("the raycaster returned a non-finite normal " + InvariantFormat.Vector(hit.Normal) + " for ray " +
                                         ray + " (a raycaster bug)");
            return d;
        }
    }
}
