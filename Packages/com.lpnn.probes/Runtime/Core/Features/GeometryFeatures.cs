using System;
using System.Numerics;
using System.Threading;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Core.Features
{
    /// <summary>Features 15–18 of lpnn.features.v1: how enclosed a point is, from 26 fixed rays of 4 cells
    /// (Documentation~/features.md), and from the same rays each point's back-face fraction (<see cref="ProbeValidity"/>).
    /// The rays are cast as far as <see cref="ProbeValidity.RayLength"/>: the features count only hits within 4 cells,
    /// the validity rule every hit (a point deep inside a thick mesh sees its back faces only from afar).</summary>
    internal static class GeometryFeatures
    {
        public const int Count = 4;
        public const int RayLengthCells = 4;
        private const int PointsPerBatch = 2048;

        /// <param name="backFaceFractions">One entry per grid point, written with the point's back-face fraction.</param>
        public static void Compute(EvaluationGrid grid, IRaycaster raycaster, float[] output, int stride, int firstFeature,
            float[] backFaceFractions, ProgressCallback progress, CancellationToken cancel)
        {
            if (raycaster == null) throw new ArgumentNullException(nameof(raycaster));
            int rays = DirectionSets.D26.GetLength(0);
            double near = grid.CellSize, far = RayLengthCells * grid.CellSize;
            var directions = new Vector3[rays];
            for (int d = 0; d < rays; d++) directions[d] = DirectionSets.Direction(DirectionSets.D26, d);
            int batchPoints = Math.Min(PointsPerBatch, grid.Count);
            var origins = new Vector3[batchPoints * rays];
            var rayDirections = new Vector3[batchPoints * rays];
            var hits = new RayHit[batchPoints * rays];
            for (int first = 0; first < grid.Count; first += batchPoints)
            {
                progress?.Invoke("casting rays", first, grid.Count);
                cancel.ThrowIfCancellationRequested();
                int points = Math.Min(batchPoints, grid.Count - first);
                int batchRays = points * rays;
                if (batchRays != origins.Length)
                {
                    origins = new Vector3[batchRays];
                    rayDirections = new Vector3[batchRays];
                    hits = new RayHit[batchRays];
                }
                for (int p = 0; p < points; p++)
                {
                    var origin = grid.GetPosition(first + p);
                    for (int d = 0; d < rays; d++)
                    {
                        origins[p * rays + d] = origin;
                        rayDirections[p * rays + d] = directions[d];
                    }
                }
                for (int r = 0; r < batchRays; r++) hits[r] = RayHit.Miss;
                raycaster.Cast(origins, rayDirections, Math.Max(ProbeValidity.RayLength, (float)far), hits);
                for (int p = 0; p < points; p++)
                {
                    Summarise(grid, first + p, hits, p * rays, rays, directions, near, far, output, (first + p) * stride + firstFeature);
                    backFaceFractions[first + p] = (float)ProbeValidity.BackFaceFraction(directions, hits, p * rays);
                }
            }
            progress?.Invoke("casting rays", grid.Count, grid.Count);
            cancel.ThrowIfCancellationRequested();
        }

        private static void Summarise(EvaluationGrid grid, int point, RayHit[] hits, int offset, int rays, Vector3[] directions,
            double near, double far, float[] output, int o)
        {
            int nearHits = 0, farHits = 0;
            double nearest = far;
            double nx = 0, ny = 0, nz = 0;
            int normals = 0;
            for (int d = 0; d < rays; d++)
            {
                var hit = hits[offset + d];
                double t = hit.Distance;
                if (double.IsNaN(t) || t < 0)
                    throw new FeatureException("the raycaster returned distance " + InvariantFormat.Number(hit.Distance) + " for ray " + d +
                                               " of point " + point + " (id " + grid.GetId(point) + "); distances must be ≥ 0 or +∞ for a miss");
                if (!(t <= far)) continue;
                farHits++;
                if (t <= near) nearHits++;
                if (t < nearest) nearest = t;
                var n = Double3.FromVector3(hit.Normal);
                if (!n.IsFinite)
                    throw new FeatureException("the raycaster returned a non-finite normal " + InvariantFormat.Vector(hit.Normal) + " for ray " + d + " of point " + point);
                double length = n.Length;
                if (length == 0) continue; // a hit without a usable normal still counts as occlusion
                n = n * (1 / length);
                var dir = directions[d];
                if (n.X * dir.X + n.Y * dir.Y + n.Z * dir.Z > 0) n = -n; // face the ray origin: winding must not matter
                nx += n.X;
                ny += n.Y;
                nz += n.Z;
                normals++;
            }
            output[o] = (float)((double)nearHits / rays);
            output[o + 1] = (float)((double)farHits / rays);
            output[o + 2] = (float)(nearest / far);
            output[o + 3] = normals == 0 ? 0f : (float)(1 - Math.Sqrt(nx * nx + ny * ny + nz * nz) / normals);
        }
    }
}
