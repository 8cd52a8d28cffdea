using System.Collections.Generic;

namespace Lpnn.Probes.Editor
{
    /// <summary>What the inspector shows about one volume's steps (done, summary, timing, last error), kept beside the
    /// session's data but apart from it: the session holds results, this holds how they were reported. A step's ✓ stays
    /// only while the data it reported is still the session's (a new grid drops the lighting and features, so their ✓
    /// lines go too).</summary>
    internal sealed class StepStates
    {
        private static readonly Dictionary<ObjectKey, StepStates> All = new Dictionary<ObjectKey, StepStates>();

        private readonly Dictionary<PipelineStep, StepState> _steps = new Dictionary<PipelineStep, StepState>
        {
            { PipelineStep.Grid, new StepState("Volume") },
            { PipelineStep.Lighting, new StepState("Lighting data") },
            { PipelineStep.Features, new StepState("Features") },
            { PipelineStep.Scoring, new StepState("Scoring") },
            { PipelineStep.Placement, new StepState("Placement") },
        };
        /// <summary>The data each step's ✓ describes (the grid, the SH array, the feature set, the scores array).</summary>
        private readonly Dictionary<PipelineStep, object> _reported = new Dictionary<PipelineStep, object>();

        public StepState Export { get; } = new StepState("Capture export");

        public StepState this[PipelineStep step] => _steps[step];

        public static StepStates For(LpnnVolume volume)
        {
            var key = ObjectKey.Of(volume);
            if (!All.TryGetValue(key, out var states))
            {
                states = new StepStates();
                All[key] = states;
            }
            return states;
        }

        /// <summary>Records that the step's ✓ describes the current data of the session.</summary>
        public void Reported(PipelineStep step, LpnnSession session, LpnnVolume volume) => _reported[step] = DataOf(step, session, volume);

        /// <summary>Resets every step whose reported data is no longer the session's (replaced, or dropped by a new grid).</summary>
        public void DropStale(LpnnSession session, LpnnVolume volume)
        {
            foreach (var entry in _steps)
            {
                if (!entry.Value.Done || !_reported.TryGetValue(entry.Key, out var reported)) continue;
                var current = DataOf(entry.Key, session, volume);
                if (current != null && ReferenceEquals(current, reported)) continue;
                if (entry.Key == PipelineStep.Placement) continue;  // the group, not the session, holds placed probes
                entry.Value.Reset();
                _reported.Remove(entry.Key);
            }
        }

        private static object DataOf(PipelineStep step, LpnnSession session, LpnnVolume volume)
        {
            switch (step)
            {
                case PipelineStep.Grid: return session.Grid;
                case PipelineStep.Lighting: return session.Sh;
                case PipelineStep.Features: return session.Features;
                case PipelineStep.Scoring: return LpnnScores.For(volume).IsEmpty ? null : LpnnScores.For(volume).Scores;  // the Library copy once per session
                default: return null;
            }
        }
    }
}
