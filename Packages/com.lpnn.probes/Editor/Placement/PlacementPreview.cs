using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Selection;

namespace Lpnn.Probes.Editor
{
    /// <summary>The selection for the current settings, recomputed only when the settings, the scores or the grid change,
    /// so the inspector can show a live probe count while a slider moves. The tolerance policy evaluates the placement
    /// error a dozen or more times, far too slow for every repaint: it runs only when asked (<see cref="Search"/>) and its
    /// result is shown until the inputs change.</summary>
    public sealed class PlacementPreview
    {
        private SelectionSettings _settings;
        private float[] _scores;
        private EvaluationGrid _grid;
        private SelectionResult _result;
        private string _error;

        /// <summary>The result, or null with <paramref name="error"/> set when the settings cannot be applied (or, for the
        /// tolerance policy, when no search has run for them yet).</summary>
        public SelectionResult Get(EvaluationGrid grid, LpnnScoreRecord record, SelectionSettings settings, out string error)
        {
            var scores = record.Scores;
            if (!SameInputs(grid, scores, settings) || (_result == null && _error == null))
            {
                Remember(grid, scores, settings);
                if (settings.Policy == SelectionPolicy.Tolerance)
                {
                    _result = null;
                    _error = "The tolerance policy measures the placement error of many probe counts: press 'Find probes' to search.";
                }
                else
                {
                    Compute(() => ProbeSelector.Select(PlacementInputs.Scored(grid, record), settings, null));
                }
            }
            error = _error;
            return _result;
        }

        /// <summary>Runs the tolerance search for these inputs and keeps its result for <see cref="Get"/> and Apply.</summary>
        public SelectionResult Search(EvaluationGrid grid, LpnnScoreRecord record, SelectionSettings settings, IPlacementErrorMeasure measure)
        {
            Remember(grid, record.Scores, settings);
            _result = ProbeSelector.Select(PlacementInputs.Scored(grid, record), settings, measure);
            _error = null;
            return _result;
        }

        private void Remember(EvaluationGrid grid, float[] scores, SelectionSettings settings)
        {
            _grid = grid;
            _scores = scores;
            _settings = settings;
        }

        private void Compute(System.Func<SelectionResult> select)
        {
            try
            {
                _result = select();
                _error = null;
            }
            catch (Core.LpnnException e)
            {
                _result = null;
                _error = e.Message;
            }
        }

        private bool SameInputs(EvaluationGrid grid, float[] scores, SelectionSettings settings) =>
            grid == _grid && scores == _scores && settings.Policy == _settings.Policy && settings.Value.Equals(_settings.Value) &&
            settings.KeepBoundsCorners == _settings.KeepBoundsCorners;
    }
}
