using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Selection;

namespace Lpnn.Probes.Editor
{
    /// <summary>The selection for the current settings, recomputed only when the settings, the scores or the grid change,
    /// so the inspector can show a live probe count while a slider moves.</summary>
    public sealed class PlacementPreview
    {
        private SelectionSettings _settings;
        private float[] _scores;
        private EvaluationGrid _grid;
        private SelectionResult _result;
        private string _error;

        /// <summary>The result, or null with <paramref name="error"/> set when the settings cannot be applied.</summary>
        public SelectionResult Get(EvaluationGrid grid, float[] scores, SelectionSettings settings, out string error)
        {
            if (grid != _grid || scores != _scores || !Same(settings, _settings) || (_result == null && _error == null))
            {
                _grid = grid;
                _scores = scores;
                _settings = settings;
                try
                {
                    _result = ProbeSelector.Select(grid, scores, settings);
                    _error = null;
                }
                catch (Core.LpnnException e)
                {
                    _result = null;
                    _error = e.Message;
                }
            }
            error = _error;
            return _result;
        }

        private static bool Same(SelectionSettings a, SelectionSettings b) =>
            a.Policy == b.Policy && a.Value.Equals(b.Value) && a.KeepBoundsCorners == b.KeepBoundsCorners;
    }
}
