using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Pipeline;
using Lpnn.Probes.Core.Quality;
using Lpnn.Probes.Core.Selection;
using Lpnn.Probes.Core.Scoring;

namespace Lpnn.Probes.Editor
{
    /// <summary>The selection for the current settings, recomputed only when the settings, the scores or the grid change,
    /// so the inspector can show a live probe count while a slider moves. The tolerance policy evaluates the placement
    /// error a dozen or more times, far too slow for every repaint: it runs only when asked (<see cref="Search"/>) and its
    /// result is shown until the inputs change.</summary>
    internal sealed class PlacementPreview
    {
        private SelectionSettings _settings;
        /// <summary>What the selection was made from: the scores (Network) or the insertion ranking (Insertion).</summary>
        private object _source;
        private EvaluationGrid _grid;
        private SelectionResult _result;
        private string _error;

        /// <summary>The result, or null with <paramref name="error"/> set when the settings cannot be applied (or, for the
        /// tolerance policy, when no search has run for them yet).</summary>
        public SelectionResult Get(EvaluationGrid grid, ScoreRecord record, SelectionSettings settings, out string error) =>
            Get(grid, record.Scores, settings, () => ProbeSelector.Select(PlacementInputs.Scored(grid, record), settings, null), out error);

        /// <summary>As <see cref="Get(EvaluationGrid, ScoreRecord, SelectionSettings, out string)"/> over the insertion ranking
        /// (the valid points only; null <paramref name="valid"/>: all), as Apply selects before its refinement (Core's
        /// ApplySteps.PreviewByInsertion): with <paramref name="pins"/> the ranking must be the pinned one, and the pins are kept
        /// and counted in the policy's probes.</summary>
        public SelectionResult GetRanked(EvaluationGrid grid, int[] ranking, bool[] valid, SelectionSettings settings, Pins pins, out string error) =>
            Get(grid, ranking, settings, () => ApplySteps.PreviewByInsertion(grid, valid, ranking, settings, pins), out error);

        private SelectionResult Get(EvaluationGrid grid, object source, SelectionSettings settings, System.Func<SelectionResult> select, out string error)
        {
            if (!SameInputs(grid, source, settings) || (_result == null && _error == null))
            {
                Remember(grid, source, settings);
                if (settings.Policy == SelectionPolicy.Tolerance)
                {
                    _result = null;
                    _error = "The tolerance policy measures the placement error of many probe counts: press 'Find probes' to search.";
                }
                else
                {
                    Compute(select);
                }
            }
            error = _error;
            return _result;
        }

        /// <summary>Runs the tolerance search for these inputs and keeps its result for <see cref="Get(EvaluationGrid, ScoreRecord, SelectionSettings, out string)"/> and Apply.</summary>
        public SelectionResult Search(EvaluationGrid grid, ScoreRecord record, SelectionSettings settings, IPlacementErrorMeasure measure) =>
            Keep(grid, record.Scores, settings, ProbeSelector.Select(PlacementInputs.Scored(grid, record), settings, measure));

        /// <summary>The tolerance search over the insertion ranking (valid points only), as Apply searches before its
        /// refinement (Core's ApplySteps.SelectByInsertion): with <paramref name="pins"/> the answer holds every pin.</summary>
        public SelectionResult SearchRanked(EvaluationGrid grid, int[] ranking, bool[] valid, SelectionSettings settings, IPlacementErrorMeasure measure,
            Pins pins) =>
            Keep(grid, ranking, settings, ApplySteps.SelectByInsertion(grid, valid, ranking, null, settings, measure, false, null, null, default, pins));

        /// <summary>The tolerance search over an insertion order read only as far as the search's prefixes (as Apply does,
        /// LpnnPipeline.SelectByInsertion), not the whole ranking; kept under the order for <see cref="Kept"/>. With
        /// <paramref name="pins"/> the order must start from them (PlacementInputs' pinned order).</summary>
        public SelectionResult SearchPrefixes(EvaluationGrid grid, InsertionOrder order, bool[] valid, SelectionSettings settings,
            IPlacementErrorMeasure measure, Pins pins, ProgressCallback progress, System.Threading.CancellationToken cancel) =>
            Keep(grid, order, settings, ApplySteps.SelectByInsertion(grid, valid, null, order, settings, measure, false, null, progress, cancel, pins));

        /// <summary>The result kept for exactly these inputs, or null (never computes).</summary>
        public SelectionResult Kept(EvaluationGrid grid, object source, SelectionSettings settings) =>
            source != null && SameInputs(grid, source, settings) ? _result : null;

        private SelectionResult Keep(EvaluationGrid grid, object source, SelectionSettings settings, SelectionResult result)
        {
            Remember(grid, source, settings);
            _result = result;
            _error = null;
            return _result;
        }

        private void Remember(EvaluationGrid grid, object source, SelectionSettings settings)
        {
            _grid = grid;
            _source = source;
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

        private bool SameInputs(EvaluationGrid grid, object source, SelectionSettings settings) =>
            grid == _grid && ReferenceEquals(source, _source) && settings.Policy == _settings.Policy && settings.Value.Equals(_settings.Value) &&
            settings.KeepBoundsCorners == _settings.KeepBoundsCorners;
    }
}
