using System;
using System.Numerics;
using System.Threading;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Sh;

namespace Lpnn.Probes.Core.Features
{
    /// <summary>Extracts lpnn.features.v1 for every point of a grid from its SH and a raycaster.</summary>
    public static class FeatureExtractor
    {
        public static FeatureSchema Schema => FeatureSchema.LpnnV1;

        private const int PointsPerSampleBatch = 4096;

        /// <summary>The progress stage of <see cref="SampleLighting"/> (the Lighting step's, in the editor and the rehearsal).</summary>
        internal const string LightingStage = "sampling lighting";

        /// <summary>Asks the light sampler for the SH at every evaluation point (in batches, with progress and
        /// cancel) and checks every value is finite.</summary>
        public static float[] SampleLighting(EvaluationGrid grid, ILightSampler sampler, ProgressCallback progress = null,
            CancellationToken cancel = default)
        {
            if (grid == null) throw new ArgumentNullException(nameof(grid));
            if (sampler == null) throw new ArgumentNullException(nameof(sampler));
            var sh = new float[(long)grid.Count * ShMath.FloatsPerProbe];
            int batch = Math.Min(PointsPerSampleBatch, grid.Count);
            var positions = new Vector3[batch];
            var batchSh = new float[batch * ShMath.FloatsPerProbe];
            for (int first = 0; first < grid.Count; first += batch)
            {
                // Progress, then cancel: the editor reads its Cancel button inside the progress call, so the check right after
                // it stops before any further work (Tests/Core/ApplyCancelTests).
                progress?.Invoke(LightingStage, first, grid.Count);
                cancel.ThrowIfCancellationRequested();
                int count = Math.Min(batch, grid.Count - first);
                if (count != positions.Length)
                {
                    positions = new Vector3[count];
                    batchSh = new float[count * ShMath.FloatsPerProbe];
                }
                for (int p = 0; p < count; p++) positions[p] = grid.GetPosition(first + p);
                sampler.Sample(positions, batchSh);
                Array.Copy(batchSh, 0, sh, (long)first * ShMath.FloatsPerProbe, (long)count * ShMath.FloatsPerProbe);
            }
            progress?.Invoke(LightingStage, grid.Count, grid.Count);
            cancel.ThrowIfCancellationRequested();
            CheckFinite(grid, sh);
            return sh;
        }

        /// <summary>The full lpnn.features.v1 matrix (grid.Count × 19), the scene scale it is relative to, and each point's
        /// back-face fraction from the same rays (<see cref="ProbeValidity"/>).</summary>
        public static FeatureSet Extract(EvaluationGrid grid, float[] sh, IRaycaster raycaster, ProgressCallback progress = null,
            CancellationToken cancel = default) =>
            Extract(grid, sh, raycaster, null, progress, cancel);

        /// <summary>As the public overload, and with <paramref name="colliders"/> (null: none) the points inside solid colliders,
        /// which the rays cannot see, get back-face fraction 1 (<see cref="InsideColliders"/>): invalid.</summary>
        internal static FeatureSet Extract(EvaluationGrid grid, float[] sh, IRaycaster raycaster, IColliderQuery colliders, ProgressCallback progress,
            CancellationToken cancel)
        {
            if (grid == null) throw new ArgumentNullException(nameof(grid));
            if (sh == null || sh.Length != (long)grid.Count * ShMath.FloatsPerProbe)
                throw new ArgumentException("need 27 SH floats per evaluation point (" + grid.Count + " points)", nameof(sh));
            CheckFinite(grid, sh);
            int stride = Schema.Count;
            var values = new float[(long)grid.Count * stride];
            double scale = SceneScale.Compute(sh, grid.Count);
            LightingFeatures.Compute(grid, sh, scale, values, stride, progress, cancel);
            var backFaceFractions = new float[grid.Count];
            GeometryFeatures.Compute(grid, raycaster, values, stride, LightingFeatures.Count, backFaceFractions, progress, cancel);
            cancel.ThrowIfCancellationRequested();
            int insideColliders = 0;
            if (colliders != null)
            {
                bool[] inside = InsideColliders.Find(grid, colliders, progress, cancel);
                for (int n = 0; n < inside.Length; n++)
                {
                    if (!inside[n]) continue;
                    backFaceFractions[n] = ProbeValidity.InsideColliderFraction;
                    insideColliders++;
                }
            }
            return new FeatureSet(Schema, grid.Count, values, scale, backFaceFractions, insideColliders);
        }

        private static void CheckFinite(EvaluationGrid grid, float[] sh)
        {
            int bad = 0, first = -1;
            for (int n = 0; n < grid.Count; n++)
            {
                if (ShMath.IsFinite(sh, n * ShMath.FloatsPerProbe)) continue;
                if (first < 0) first = n;
                bad++;
            }
            if (bad == 0) return;
            throw new FeatureException(
                "the lighting at " + InvariantFormat.Count(bad) + " of " + InvariantFormat.Count(grid.Count) +
                " evaluation points is not finite (NaN or infinite SH), first at point " + first + " (id " + grid.GetId(first) +
                ", position " + InvariantFormat.Vector(grid.GetPosition(first)) + "); re-bake the lighting (or re-import the level) and extract again");
        }
    }
}
