#if LPNN_INFERENCE_ENGINE || LPNN_SENTIS
using System;
using Lpnn.Probes.Core.Scoring;
using UnityEngine;
#if LPNN_INFERENCE_ENGINE
using Unity.InferenceEngine;
#else
using Unity.Sentis;
#endif

namespace Lpnn.Probes.Editor
{
    /// <summary>Runs the ONNX model with Sentis 2.1 (Unity.Sentis) or Inference Engine 2.2+ (Unity.InferenceEngine; same
    /// API, other namespace; needle-mirror com.unity.sentis 2.1.3 / com.unity.ai.inference 2.2.0
    /// Runtime/Core/Backends/Worker.cs, TensorGeneric.cs, Serialization/ModelLoader.cs). The model and one worker are
    /// created once per model asset and backend and reused across runs; the input tensor is created and disposed per run;
    /// the output is read with DownloadToArray (a copy) and never disposed, because PeekOutput returns a tensor the
    /// worker owns.</summary>
    internal sealed class InferenceBackendRunner : IDisposable
    {
        private readonly ModelAsset _asset;
        private Model _model;
        private Worker _worker;
        private ScoringDevice _device;

        public InferenceBackendRunner(ModelAsset asset)
        {
            _asset = asset;
        }

        public bool Serves(UnityEngine.Object asset) => asset == _asset && _asset != null;

        /// <summary>Scores one cloud; throws whatever the backend throws (the caller falls back to the next device).</summary>
        public float[] Run(float[] features, int[] shape, ScoringDevice device)
        {
            EnsureWorker(device);
            using (var input = new Tensor<float>(new TensorShape(shape[0], shape[1], shape[2]), features))
            {
                _worker.SetInput(ModelCard.ContractInputName, input);
                _worker.Schedule();
                var output = _worker.PeekOutput(ModelCard.ContractOutputName) as Tensor<float>;
                if (output == null)
                    throw new ScoringException("the model's output '" + ModelCard.ContractOutputName + "' is not a float tensor; re-export it with `lpnn export`");
                return output.DownloadToArray();
            }
        }

        /// <summary>Checks the graph's input and output names against the model contract before the first run.</summary>
        public void CheckGraph(string modelName)
        {
            EnsureModel();
            bool hasInput = false, hasOutput = false;
            foreach (var input in _model.inputs) hasInput |= input.name == ModelCard.ContractInputName;
            foreach (var output in _model.outputs) hasOutput |= output.name == ModelCard.ContractOutputName;
            if (!hasInput || !hasOutput)
                throw new ScoringException("the model '" + modelName + "' has no input '" + ModelCard.ContractInputName + "' or no output '" +
                                           ModelCard.ContractOutputName + "' (Documentation~/model-contract.md); re-export it with `lpnn export`");
        }

        private void EnsureModel()
        {
            if (_model == null) _model = ModelLoader.Load(_asset);
        }

        private void EnsureWorker(ScoringDevice device)
        {
            if (_worker != null && _device == device) return;
            DisposeWorker();
            EnsureModel();
            // fp32 on both backends, kept by never quantizing: half precision turned 130,862 of 135,104 scores into ties on a
            // whole level (issue 31). Neither package has a half-precision tensor type (needle-mirror/com.unity.ai.inference
            // 2.4.0 Runtime/Core/Backends/CPU/NativeTensorArray.cs DataType: Float, Int, Short, Byte), fp16 ONNX constants are
            // widened to Float on import (Editor/ONNX/ONNXConstantsLoader.cs:146; com.unity.sentis 2.1.3 :154), and weights
            // become fp16 only through ModelQuantizer.QuantizeWeights(QuantizationType.Float16)
            // (Runtime/Core/Quantization/ModelQuantizer.cs), which this package never calls. GPU and CPU still differ in the
            // order of their fp32 reductions (up to 2.2e-3 on 135,104 points); ties are broken by grid index in ranking.
            _worker = new Worker(_model, device == ScoringDevice.GpuCompute ? BackendType.GPUCompute : BackendType.CPU);
            _device = device;
        }

        /// <summary>Drops the worker (e.g. after a failed GPU run) but keeps the loaded model.</summary>
        public void DisposeWorker()
        {
            _worker?.Dispose();
            _worker = null;
        }

        public void Dispose()
        {
            DisposeWorker();
            _model = null;
        }
    }
}
#endif
