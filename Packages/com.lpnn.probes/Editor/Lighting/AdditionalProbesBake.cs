#if !UNITY_6000_0_OR_NEWER
using System;
using System.Threading;
using Lpnn.Probes.Core;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Sh;
using Unity.Collections;
using UnityEditor;
using UnityEngine;
using UnityEngine.Rendering;
using ExperimentalLightmapping = UnityEditor.Experimental.Lightmapping;

namespace Lpnn.Probes.Editor
{
    /// <summary>Unity 2022.3: bakes the evaluation points as additional probes of a full lightmap bake
    /// (UnityEditor.Experimental.Lightmapping.SetAdditionalBakedProbes / GetAdditionalBakedProbes and
    /// UnityEditor.Lightmapping.Bake: UnityCsReference 2022.3 Editor/Mono/GI/Lightmapping.bindings.cs).
    /// 2022.3 has no way to bake probes alone, so this regenerates the scene's lighting data from its current
    /// Lighting Settings exactly as "Generate Lighting" would: callers must have the user's consent
    /// (the inspector asks; batch mode needs -lpnnBake). The requests are withdrawn afterwards so later bakes of
    /// the user do not keep baking our points.</summary>
    internal sealed class AdditionalProbesBake : IEvaluationLighting
    {
        /// <summary>Points per request id: GetAdditionalBakedProbes also returns an 8×8 depth map per probe, so the
        /// read-back memory stays bounded (64k points × 64 floats = 16 MB at a time).</summary>
        private const int PointsPerRequest = 65536;
        private const int OctahedralDepthTexels = 64;
        private readonly int _firstRequestId;
        private readonly string _scenePath;

        /// <param name="requestIdSeed">Distinguishes volumes (e.g. the volume's instance id).</param>
        /// <param name="scenePath">The volume's scene asset path; empty for a scene never saved.</param>
        public AdditionalProbesBake(int requestIdSeed, string scenePath)
        {
            _scenePath = scenePath ?? "";
            // A fixed tag in the high bits keeps our ids away from small ids other tools pick.
            _firstRequestId = 0x4C500000 ^ ((requestIdSeed & 0x3FF) << 10);
        }

        public string Description { get; private set; } = "baked at the evaluation points (additional probes of a full bake)";

        public float[] Sample(EvaluationGrid grid, ProgressCallback progress, CancellationToken cancel)
        {
            if (_scenePath.Length == 0)
                throw new LpnnException("the scene has never been saved, and Unity stores baked lighting beside the scene file; save the scene, then sample again");
            if (Lightmapping.isRunning)
                throw new LpnnException("a lighting bake is already running; wait for it to finish, then sample again");
            if (Lightmapping.TryGetLightingSettings(out var settings) && !settings.bakedGI)
                throw new LpnnException("Baked Global Illumination is off in this scene's Lighting Settings, so a bake produces no probe " +
                                        "lighting; enable it (Window > Rendering > Lighting) or use 'Interpolate Scene Probes'");
            int count = grid.Count;
            int requests = (count + PointsPerRequest - 1) / PointsPerRequest;
            var sh = new float[(long)count * ShMath.FloatsPerProbe];
            int inside = 0;
            try
            {
                for (int r = 0; r < requests; r++)
                {
                    int first = r * PointsPerRequest, length = Math.Min(PointsPerRequest, count - first);
                    var positions = new Vector3[length];
                    for (int p = 0; p < length; p++) positions[p] = grid.GetPosition(first + p).ToUnity();
                    ExperimentalLightmapping.SetAdditionalBakedProbes(_firstRequestId + r, positions);
                }
                cancel.ThrowIfCancellationRequested();
                progress?.Invoke("baking lighting (Unity's bake progress)", 0, count);
                // Synchronous bake with Unity's own cancellable progress bar; false when cancelled or failed.
                if (!Lightmapping.Bake())
                    throw new LpnnException("the lighting bake was cancelled or failed (see the console); no lighting was sampled");
                for (int r = 0; r < requests; r++)
                {
                    cancel.ThrowIfCancellationRequested();
                    int first = r * PointsPerRequest, length = Math.Min(PointsPerRequest, count - first);
                    progress?.Invoke("reading baked probes", first, count);
                    inside += Read(_firstRequestId + r, first, length, sh);
                }
                progress?.Invoke("reading baked probes", count, count);
            }
            finally
            {
                for (int r = 0; r < requests; r++) ExperimentalLightmapping.SetAdditionalBakedProbes(_firstRequestId + r, new Vector3[0]);
            }
            if (inside > 0)
                Description += "; " + InvariantFormat.Count(inside) + " points are inside geometry (invalid probes)";
            return sh;
        }

        /// <returns>How many probes Unity marked invalid (validity above one half: inside geometry).</returns>
        private static int Read(int requestId, int first, int length, float[] sh)
        {
            using (var probes = new NativeArray<SphericalHarmonicsL2>(length, Allocator.Persistent))
            using (var validity = new NativeArray<float>(length, Allocator.Persistent))
            using (var depth = new NativeArray<float>(length * OctahedralDepthTexels, Allocator.Persistent))
            {
                if (!ExperimentalLightmapping.GetAdditionalBakedProbes(requestId, probes, validity, depth))
                    throw new LpnnException("Unity returned no baked lighting for the evaluation points (request " + requestId +
                                            "); the bake may not have included them: bake again");
                int invalid = 0;
                for (int p = 0; p < length; p++)
                {
                    UnityCoreConversions.CopySh(probes[p], sh, (first + p) * ShMath.FloatsPerProbe);
                    if (validity[p] > 0.5f) invalid++;
                }
                return invalid;
            }
        }

        public void Dispose() { }
    }
}
#endif
