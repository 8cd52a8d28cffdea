// Stand-ins for the Sentis 2.1 / Inference Engine 2.2+ members used by LPNN (signatures only; see ../README.md).
// Compiled twice: as Unity.Sentis.dll (namespace Unity.Sentis; needle-mirror/com.unity.sentis tag 2.1.3) and, with
// LPNN_STUB_INFERENCE_ENGINE, as Unity.InferenceEngine.dll (namespace Unity.InferenceEngine; needle-mirror/com.unity.ai.inference
// tag 2.2.0). The members below are identical in both packages; only the namespace differs.
using System;
using System.Collections.Generic;
using UnityEngine;

#if LPNN_STUB_INFERENCE_ENGINE
namespace Unity.InferenceEngine
#else
namespace Unity.Sentis
#endif
{
    // Runtime/Core/Sentis.cs (2.1.3) / Runtime/Core/InferenceEngine.cs (2.2.0)
    public enum DeviceType { GPU = 1 << 8, CPU = 1 << 9 }

    // Runtime/Core/Sentis.cs (2.1.3) / Runtime/Core/InferenceEngine.cs (2.2.0)
    public enum BackendType { GPUCompute = 0 | DeviceType.GPU, GPUPixel = 1 | DeviceType.GPU, CPU = 0 | DeviceType.CPU }

    // Runtime/Core/Internals/ModelAsset.cs
    public class ModelAsset : ScriptableObject { }

    // Runtime/Core/Model.cs
    public class Model
    {
        public struct Input
        {
            public string name;
        }

        public struct Output
        {
            public string name;
        }

        public List<Input> inputs = new List<Input>();
        public List<Output> outputs = new List<Output>();
    }

    // Runtime/Core/Serialization/ModelLoader.cs
    public static class ModelLoader
    {
        public static Model Load(ModelAsset modelAsset) { throw null; }
    }

    // Runtime/Core/TensorShape.cs
    public struct TensorShape
    {
        public TensorShape(int d0, int d1, int d2) { throw null; }
    }

    // Runtime/Core/Tensor.cs
    public abstract class Tensor : IDisposable
    {
        public void Dispose() { }
    }

    // Runtime/Core/TensorGeneric.cs — DIVERGENCE: the real constraint is `unmanaged` (C# 7.3); mcs -langversion:7.2 gets `struct`.
    public class Tensor<T> : Tensor where T : struct
    {
        public Tensor(TensorShape shape, T[] srcData, int dataStartIndex = 0) { throw null; }
        public T[] DownloadToArray() { throw null; }
    }

    // Runtime/Core/Backends/Worker.cs
    public class Worker : IDisposable
    {
        public Worker(Model model, BackendType backendType) { throw null; }
        public void SetInput(string name, Tensor input) { }
        public void Schedule() { }
        public Tensor PeekOutput(string name) { throw null; }
        public void Dispose() { }
    }
}
