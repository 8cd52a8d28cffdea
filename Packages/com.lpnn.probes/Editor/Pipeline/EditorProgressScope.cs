using System;
using System.Diagnostics;
using System.Threading;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Numerics;
using UnityEditor;
using UnityEngine;
using Debug = UnityEngine.Debug;

namespace Lpnn.Probes.Editor
{
    /// <summary>Maps the core's ProgressCallback + CancellationToken onto Unity's cancellable progress bar
    /// (EditorUtility.DisplayCancelableProgressBar / ClearProgressBar: UnityCsReference Editor/Mono/EditorUtility.bindings.cs).
    /// The bar is always cleared on Dispose; in batch mode (no UI) stages are logged instead.</summary>
    internal sealed class EditorProgressScope : IDisposable
    {
        private const long RedrawMilliseconds = 100;
        private readonly string _title;
        private readonly CancellationTokenSource _cancel = new CancellationTokenSource();
        private readonly Stopwatch _sinceRedraw = Stopwatch.StartNew();
        private readonly bool _batch;
        private string _lastStage;

        public EditorProgressScope(string title)
        {
            _title = title;
            _batch = Application.isBatchMode;
            Callback = Report;
        }

        public ProgressCallback Callback { get; }
        public CancellationToken Token => _cancel.Token;

        private void Report(string stage, long done, long total)
        {
            float fraction = total > 0 ? Mathf.Clamp01((float)((double)done / total)) : 0f;
            if (_batch)
            {
                if (stage != _lastStage) Debug.Log("[LPNN] " + _title + ": " + stage + " (" + InvariantFormat.Count(total) + ")");
                _lastStage = stage;
                return;
            }
            if (stage == _lastStage && _sinceRedraw.ElapsedMilliseconds < RedrawMilliseconds && done < total) return;
            _lastStage = stage;
            _sinceRedraw.Reset();
            _sinceRedraw.Start();
            string info = stage + ": " + InvariantFormat.Count(done) + " / " + InvariantFormat.Count(total);
            if (EditorUtility.DisplayCancelableProgressBar(_title, info, fraction)) _cancel.Cancel();
        }

        public void Dispose()
        {
            if (!_batch) EditorUtility.ClearProgressBar();
            _cancel.Dispose();
        }
    }
}
