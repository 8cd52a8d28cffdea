#if UNITY_6000_0_OR_NEWER
using System;
using System.Threading;
using Lpnn.Probes.Core;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Sh;
using Unity.Collections;
using UnityEditor;
using UnityEngine;
using UnityEngine.LightTransport;
using UnityEngine.LightTransport.PostProcessing;
using UnityEngine.Rendering;
using NumericsVector3 = System.Numerics.Vector3;

namespace Lpnn.Probes.Editor
{
    /// <summary>Unity 6: lights each evaluation point with Unity's light baker through the public LightTransport API
    /// (UnityCsReference 6000.0 Editor/Mono/GI/InputExtraction.cs, DeviceContext.bindings.cs, RadeonRaysDeviceContext.bindings.cs,
    /// World.bindings.cs, ProbeIntegrator.bindings.cs, PostProcessing.bindings.cs). The scene is extracted and integrated in
    /// memory: no bake is started, no LightingDataAsset, lightmap or probe of the user is written. The call sequence
    /// (extract, populate the world, integrate direct and indirect radiance, window the direct part, scale the indirect
    /// part, add, convolve to irradiance, convert to Unity's format, de-ring, read back) is the one Unity's own Adaptive
    /// Probe Volumes use (SRP Core ProbeGIBaking.LightTransport.cs). Needs a GPU the RadeonRays context can use.</summary>
    internal sealed class LightTransportProbeSampler : IEvaluationLighting, ILightSampler
    {
        private const float PushOff = 0.0001f;
        private const int ShFloats = ShMath.FloatsPerProbe;
        private readonly RadeonRaysContext _context = new RadeonRaysContext();
        private readonly RadeonRaysWorld _world = new RadeonRaysWorld();
        private readonly RadeonRaysProbeIntegrator _integrator = new RadeonRaysProbeIntegrator();
        private readonly RadeonRaysProbePostProcessor _postProcessor = new RadeonRaysProbePostProcessor();
        // Unity's own probe baker always gives the integrator a progress state (SRP Core ProbeGIBaking.LightTransport.cs).
        private readonly BakeProgressState _integrationProgress = new BakeProgressState();
        // Unity's default Lighting Settings (32 direct, 512 indirect, multiplier 4) when the scene has none.
        private readonly ProbeSampleCounts _samples = ProbeSampleCounts.FromLightingSettings(32, 512, 256, 4f);
        private readonly int _bounces = 2;
        private readonly float _indirectScale = 1f;
        private bool _prepared;
        private int _capacity;
        private BufferID _positions, _direct, _windowedDirect, _indirect, _scaledIndirect, _combined, _irradiance;

        public string Description { get; private set; } = "integrated at the evaluation points with LightTransport (no lighting data written)";

        public LightTransportProbeSampler()
        {
            // The scene's own sample counts, bounces and indirect intensity, scaled for probes as Unity's probe baker does.
            if (Lightmapping.TryGetLightingSettings(out var settings))
            {
                _samples = ProbeSampleCounts.FromLightingSettings(settings.directSampleCount, settings.indirectSampleCount,
                                                                  settings.environmentSampleCount, settings.lightProbeSampleCountMultiplier);
                _bounces = Math.Max(0, settings.maxBounces);
                _indirectScale = settings.indirectScale;
            }
            Description += " — " + _samples.Direct + " direct / " + _samples.Indirect + " indirect samples per point, " + _bounces + " bounces";
        }

        public float[] Sample(EvaluationGrid grid, ProgressCallback progress, CancellationToken cancel)
        {
            Prepare(progress, cancel);
            return FeatureExtractor.SampleLighting(grid, this, progress, cancel);
        }

        /// <summary>Extraction and PopulateWorld are single native calls (UnityCsReference 6000.0 Editor/Mono/GI/InputExtraction.cs)
        /// that cannot be interrupted, so progress is named before each and cancel is honoured between them.</summary>
        private void Prepare(ProgressCallback progress, CancellationToken cancel)
        {
            if (_prepared) return;
            cancel.ThrowIfCancellationRequested();
            progress?.Invoke("extracting the scene for the light baker", 0, 3);
            if (!InputExtraction.ExtractFromScene(out var input))
                throw new LpnnException("Unity could not extract the scene for light baking (see the console); check that lights and " +
                                        "static renderers are set up for baked lighting, or use 'Interpolate Scene Probes'");
            if (!_context.Initialize())
                throw new LpnnException("the GPU light baker (RadeonRays) could not start on this machine — for example in batch mode with " +
                                        "-nographics or without an OpenCL-capable GPU; run with a GPU or use 'Interpolate Scene Probes'");
            cancel.ThrowIfCancellationRequested();
            progress?.Invoke("preparing the scene for the light baker (PopulateWorld)", 1, 3);
            using (var worldProgress = new BakeProgressState())
            {
                if (!InputExtraction.PopulateWorld(input, worldProgress, _context, _world))
                    throw new LpnnException("Unity could not prepare the scene for light baking (PopulateWorld failed; see the console)");
            }
            cancel.ThrowIfCancellationRequested();
            progress?.Invoke("starting the probe post-processing", 2, 3);
            if (!_postProcessor.Initialize(_context))
                throw new LpnnException("Unity's probe post-processing could not start (see the console)");
            _prepared = true;
        }

        public void Sample(NumericsVector3[] positions, float[] sh)
        {
            int count = positions.Length;
            if (count == 0) return;
            EnsureBuffers(count);
            var positionSlice = new BufferSlice<Vector3>(_positions, 0);
            var upload = new NativeArray<Vector3>(count, Allocator.Persistent);
            try
            {
                for (int p = 0; p < count; p++) upload[p] = positions[p].ToUnity();
                var written = _context.CreateEvent();
                _context.WriteBuffer(positionSlice, upload, written);
                Check(_context.Wait(written), "uploading positions");
                _context.DestroyEvent(written);
            }
            finally
            {
                upload.Dispose();
            }

            var direct = new BufferSlice<SphericalHarmonicsL2>(_direct, 0);
            var windowed = new BufferSlice<SphericalHarmonicsL2>(_windowedDirect, 0);
            var indirect = new BufferSlice<SphericalHarmonicsL2>(_indirect, 0);
            var combined = new BufferSlice<SphericalHarmonicsL2>(_combined, 0);
            var irradiance = new BufferSlice<SphericalHarmonicsL2>(_irradiance, 0);
            _integrator.Prepare(_context, _world, positionSlice, PushOff, _bounces);
            _integrator.SetProgressReporter(_integrationProgress);
            Check(_integrator.IntegrateDirectRadiance(_context, 0, count, _samples.Direct, false, direct), "direct light");
            Check(_integrator.IntegrateIndirectRadiance(_context, 0, count, _samples.Indirect, false, indirect), "indirect light");
            Check(_postProcessor.WindowSphericalHarmonicsL2(_context, direct, windowed, count), "windowing");
            if (_indirectScale != 1f)
            {
                var scaled = new BufferSlice<SphericalHarmonicsL2>(_scaledIndirect, 0);
                Check(_postProcessor.ScaleSphericalHarmonicsL2(_context, indirect, scaled, count, _indirectScale), "indirect intensity");
                indirect = scaled;
            }
            Check(_postProcessor.AddSphericalHarmonicsL2(_context, windowed, indirect, combined, count), "combining");
            Check(_postProcessor.ConvolveRadianceToIrradiance(_context, combined, irradiance, count), "irradiance");
            Check(_postProcessor.ConvertToUnityFormat(_context, irradiance, combined, count), "conversion to Unity's SH format");
            Check(_postProcessor.DeringSphericalHarmonicsL2(_context, combined, combined, count), "de-ringing");

            using (var result = new NativeArray<SphericalHarmonicsL2>(count, Allocator.Persistent))
            {
                var read = _context.CreateEvent();
                _context.ReadBuffer(combined, result, read);
                Check(_context.Flush(), "flushing");
                Check(_context.Wait(read), "reading back");
                _context.DestroyEvent(read);
                for (int p = 0; p < count; p++) UnityCoreConversions.CopySh(result[p], sh, p * ShFloats);
            }
        }

        private void EnsureBuffers(int count)
        {
            if (count <= _capacity) return;
            DestroyBuffers();
            ulong shElements = (ulong)count * ShFloats;
            _positions = _context.CreateBuffer((ulong)count, 12);
            _direct = _context.CreateBuffer(shElements, 4);
            _windowedDirect = _context.CreateBuffer(shElements, 4);
            _indirect = _context.CreateBuffer(shElements, 4);
            _scaledIndirect = _context.CreateBuffer(shElements, 4);
            _combined = _context.CreateBuffer(shElements, 4);
            _irradiance = _context.CreateBuffer(shElements, 4);
            _capacity = count;
        }

        private void DestroyBuffers()
        {
            if (_capacity == 0) return;
            foreach (var id in new[] { _positions, _direct, _windowedDirect, _indirect, _scaledIndirect, _combined, _irradiance })
                _context.DestroyBuffer(id);
            _capacity = 0;
        }

        private static void Check(IProbeIntegrator.Result result, string what)
        {
            if (result.type == IProbeIntegrator.ResultType.Success) return;
            throw new LpnnException("Unity's light baker failed while integrating " + what + " (" + result.type + ": " + result.message +
                                    "); check the console, or use 'Interpolate Scene Probes'");
        }

        private static void Check(bool ok, string what)
        {
            if (!ok) throw new LpnnException("Unity's light baker failed while " + what + " (see the console); try again, or use 'Interpolate Scene Probes'");
        }

        public void Dispose()
        {
            DestroyBuffers();
            _integrator.Dispose();
            _integrationProgress.Dispose();
            _postProcessor.Dispose();
            _world.Dispose();
            _context.Dispose();
        }
    }
}
#endif
