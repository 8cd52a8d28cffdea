// Stand-ins for the Unity 6 LightTransport API used by LPNN (signatures only; see ../README.md). In 6000.0 these files live
// under Editor/Mono/GI, so they belong to the editor assembly although their namespace is UnityEngine.LightTransport.
#if UNITY_6000_0_OR_NEWER
using System;
using Unity.Collections;
using UnityEngine.Rendering;

namespace UnityEngine.LightTransport
{
    // UnityCsReference 6000.0 Editor/Mono/GI/DeviceContext.bindings.cs
    public struct BufferID
    {
        public ulong Value;
    }

    // UnityCsReference 6000.0 Editor/Mono/GI/DeviceContext.bindings.cs
    public struct BufferSlice<T> where T : struct
    {
        public BufferSlice(BufferID id, ulong offset) { throw null; }
        public BufferID Id;
        public ulong Offset;
    }

    // UnityCsReference 6000.0 Editor/Mono/GI/DeviceContext.bindings.cs
    public struct EventID
    {
        public ulong Value;
    }

    // UnityCsReference 6000.0 Editor/Mono/GI/DeviceContext.bindings.cs
    public interface IDeviceContext : IDisposable
    {
        bool Initialize();
        BufferID CreateBuffer(ulong count, ulong stride);
        void DestroyBuffer(BufferID id);
        void WriteBuffer<T>(BufferSlice<T> dst, NativeArray<T> src) where T : struct;
        void ReadBuffer<T>(BufferSlice<T> src, NativeArray<T> dst) where T : struct;
        void WriteBuffer<T>(BufferSlice<T> dst, NativeArray<T> src, EventID id) where T : struct;
        void ReadBuffer<T>(BufferSlice<T> src, NativeArray<T> dst, EventID id) where T : struct;
        EventID CreateEvent();
        void DestroyEvent(EventID id);
        bool IsCompleted(EventID id);
        bool Wait(EventID id);
        bool Flush();
    }

    // UnityCsReference 6000.0 Editor/Mono/GI/RadeonRaysDeviceContext.bindings.cs
    public class RadeonRaysContext : IDeviceContext
    {
        public RadeonRaysContext() { }
        public void Dispose() { }
        public bool Initialize() { throw null; }
        public BufferID CreateBuffer(ulong count, ulong stride) { throw null; }
        public void DestroyBuffer(BufferID id) { }
        public void ReadBuffer<T>(BufferSlice<T> src, NativeArray<T> dst) where T : struct { }
        public void ReadBuffer<T>(BufferSlice<T> src, NativeArray<T> dst, EventID id) where T : struct { }
        public void WriteBuffer<T>(BufferSlice<T> dst, NativeArray<T> src) where T : struct { }
        public void WriteBuffer<T>(BufferSlice<T> dst, NativeArray<T> src, EventID id) where T : struct { }
        public EventID CreateEvent() { throw null; }
        public void DestroyEvent(EventID id) { }
        public bool IsCompleted(EventID id) { throw null; }
        public bool Wait(EventID id) { throw null; }
        public bool Flush() { throw null; }
    }

    // UnityCsReference 6000.0 Editor/Mono/GI/World.bindings.cs
    public interface IWorld : IDisposable { }

    // UnityCsReference 6000.0 Editor/Mono/GI/World.bindings.cs
    public class RadeonRaysWorld : IWorld
    {
        public void Dispose() { }
    }

    // UnityCsReference 6000.0 Editor/Mono/GI/ProgressState.bindings.cs
    public class BakeProgressState : IDisposable
    {
        public BakeProgressState() { }
        public void Dispose() { }
    }

    // UnityCsReference 6000.0 Editor/Mono/GI/InputExtraction.cs
    public static class InputExtraction
    {
        public class BakeInput { }
        public static bool ExtractFromScene(out BakeInput bakeInput) { throw null; }
        public static bool PopulateWorld(BakeInput bakeInput, BakeProgressState progress, IDeviceContext context, IWorld world) { throw null; }
    }

    // UnityCsReference 6000.0 Editor/Mono/GI/ProbeIntegrator.bindings.cs
    // DIVERGENCE: the real IProbeIntegrator is an interface with nested ResultType/Result; mcs (C# 7.2) cannot declare
    // nested types in an interface, so it is an abstract class here. LPNN never implements or stores it; it only names
    // IProbeIntegrator.ResultType and IProbeIntegrator.Result, which is the same source text either way.
    public abstract class IProbeIntegrator : IDisposable
    {
        public enum ResultType : uint { Success = 0, Cancelled, JobFailed, OutOfMemory, InvalidInput, LowLevelAPIFailure, IOFailed, Undefined }

        public struct Result
        {
            public ResultType type;
            public string message;
        }

        public abstract void Dispose();
    }

    // UnityCsReference 6000.0 Editor/Mono/GI/ProbeIntegrator.bindings.cs
    public class RadeonRaysProbeIntegrator : IProbeIntegrator
    {
        public void Prepare(IDeviceContext context, IWorld world, BufferSlice<Vector3> positions, float pushoff, int bounceCount) { }
        public Result IntegrateDirectRadiance(IDeviceContext context, int positionOffset, int positionCount, int sampleCount,
            bool ignoreEnvironment, BufferSlice<SphericalHarmonicsL2> radianceEstimateOut) { throw null; }
        public Result IntegrateIndirectRadiance(IDeviceContext context, int positionOffset, int positionCount, int sampleCount,
            bool ignoreEnvironment, BufferSlice<SphericalHarmonicsL2> radianceEstimateOut) { throw null; }
        public override void Dispose() { }
    }
}

namespace UnityEngine.LightTransport.PostProcessing
{
    // UnityCsReference 6000.0 Editor/Mono/GI/PostProcessing.bindings.cs
    public interface IProbePostProcessor : IDisposable { }

    // UnityCsReference 6000.0 Editor/Mono/GI/PostProcessing.bindings.cs
    public class RadeonRaysProbePostProcessor : IProbePostProcessor
    {
        public bool Initialize(IDeviceContext context) { throw null; }
        public bool ConvolveRadianceToIrradiance(IDeviceContext context, BufferSlice<SphericalHarmonicsL2> radianceIn, BufferSlice<SphericalHarmonicsL2> irradianceOut, int probeCount) { throw null; }
        public bool ConvertToUnityFormat(IDeviceContext context, BufferSlice<SphericalHarmonicsL2> irradianceIn, BufferSlice<SphericalHarmonicsL2> irradianceOut, int probeCount) { throw null; }
        public bool AddSphericalHarmonicsL2(IDeviceContext context, BufferSlice<SphericalHarmonicsL2> a, BufferSlice<SphericalHarmonicsL2> b, BufferSlice<SphericalHarmonicsL2> sum, int probeCount) { throw null; }
        public bool ScaleSphericalHarmonicsL2(IDeviceContext context, BufferSlice<SphericalHarmonicsL2> shIn, BufferSlice<SphericalHarmonicsL2> shOut, int probeCount, float scale) { throw null; }
        public bool WindowSphericalHarmonicsL2(IDeviceContext context, BufferSlice<SphericalHarmonicsL2> shIn, BufferSlice<SphericalHarmonicsL2> shOut, int probeCount) { throw null; }
        public bool DeringSphericalHarmonicsL2(IDeviceContext context, BufferSlice<SphericalHarmonicsL2> shIn, BufferSlice<SphericalHarmonicsL2> shOut, int probeCount) { throw null; }
        public void Dispose() { }
    }
}
#endif
