using System;
using System.Threading;
using Lpnn.Probes.Core.Features;

namespace Lpnn.Probes.Core.Selection
{
    /// <summary>A placement-error measure that reports progress and honours cancel before each evaluation. One evaluation is a
    /// tetrahedralisation and a pass over every point (seconds at 10⁵–10⁶ points), and the tolerance search runs up to
    /// <see cref="MaxEvaluations"/> of them with no other progress call (issue 31), so this is the search's cancel point.</summary>
    internal sealed class ReportingMeasure : IPlacementErrorMeasure
    {
        public const string Stage = "Tolerance search: placement error of a probe count";
        private readonly IPlacementErrorMeasure _inner;
        private readonly ProgressCallback _progress;
        private readonly CancellationToken _cancel;
        private readonly long _total;
        private long _done;

        private ReportingMeasure(IPlacementErrorMeasure inner, int candidates, ProgressCallback progress, CancellationToken cancel)
        {
            _inner = inner;
            _progress = progress;
            _cancel = cancel;
            _total = MaxEvaluations(candidates);
        }

        /// <summary><paramref name="measure"/> wrapped, or null when it is null (the policies that measure nothing).</summary>
        public static IPlacementErrorMeasure Wrap(IPlacementErrorMeasure measure, int candidates, ProgressCallback progress, CancellationToken cancel) =>
            measure == null ? null : new ReportingMeasure(measure, candidates, progress, cancel);

        /// <summary>The tolerance search's bound on evaluations over <paramref name="candidates"/> points: 2·⌈log₂N⌉ + 2
        /// (<see cref="ToleranceSearch"/>).</summary>
        public static long MaxEvaluations(int candidates)
        {
            if (candidates < 0) throw new ArgumentOutOfRangeException(nameof(candidates), candidates, "a point count cannot be negative");
            int log = 0;
            while ((1L << log) < candidates) log++;
            return 2L * log + 2;
        }

        public double MeanError(int[] probeIndices)
        {
            _cancel.ThrowIfCancellationRequested();
            _progress?.Invoke(Stage, Math.Min(_done, _total), _total);
            _cancel.ThrowIfCancellationRequested();  // a Cancel pressed in the progress call stops before the evaluation
            double error = _inner.MeanError(probeIndices);
            _done++;
            return error;
        }
    }
}
