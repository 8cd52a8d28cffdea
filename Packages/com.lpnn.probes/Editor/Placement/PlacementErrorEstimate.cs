using System;
using Lpnn.Probes.Core;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Quality;
using Lpnn.Probes.Core.Selection;

namespace Lpnn.Probes.Editor
{
    /// <summary>The inspector's estimated error of the current selection (Documentation~/quality.md §2): Unity's
    /// tetrahedralisation of the selected probes, interpolated at every evaluation point and compared with the Lighting
    /// step's SH. Computed once per selection; automatically for grids up to <see cref="LivePointLimit"/> points (tens of
    /// milliseconds), on request above.</summary>
    internal sealed class PlacementErrorEstimate
    {
        /// <summary>Up to this many evaluation points the estimate follows the settings live.</summary>
        public const int LivePointLimit = 50000;

        private SelectionResult _selection;
        private float[] _sh;
        private string _text;
        private bool _failed;

        /// <summary>True when the text for this selection is known (computed, or failed with a reason).</summary>
        public bool Has(SelectionResult selection, LpnnSession session) => selection == _selection && session.Sh == _sh && _text != null;

        /// <summary>Whether this grid is small enough to estimate on every change of the selection.</summary>
        public static bool IsLive(EvaluationGrid grid) => grid.Count <= LivePointLimit;

        /// <summary>The readout line for the selection, computing it if needed; <paramref name="failed"/> when it could not
        /// be estimated (the text then says why).</summary>
        public string Get(SelectionResult selection, LpnnSession session, EvaluationGrid grid, out bool failed)
        {
            if (!Has(selection, session))
            {
                _selection = selection;
                _sh = session.Sh;
                try
                {
                    var result = PlacementInputs.Evaluator(session, grid).Evaluate(selection.Indices);
                    _text = Describe(result) + "\n" + DescribeInUse(result, session.InUse);
                    _failed = false;
                }
                catch (LpnnException e)
                {
                    _text = "Estimated error unavailable: " + e.Message;
                    _failed = true;
                }
            }
            failed = _failed;
            return _text;
        }

        /// <summary>"Estimated error 0.031 mean, 0.084 at the 95th percentile (SMAPE 0.027); 312 points outside the probes".</summary>
        public static string Describe(PlacementErrorResult result)
        {
            string text = "Estimated error " + Round(result.Irradiance.Mean) + " mean, " + Round(result.Irradiance.P95) +
                          " at the 95th percentile (YCoCg SMAPE " + Round(result.Smape.Mean) + ")";
            if (result.OutsidePoints > 0) text += "; " + InvariantFormat.Count(result.OutsidePoints) + " points outside the probes take their nearest hull point";
            return text + ".";
        }

        /// <summary>"Estimated error at the 1,234 points in use (reachable): …" (the figure `lpnn place` reports), or why it is
        /// not known.</summary>
        public static string DescribeInUse(PlacementErrorResult result, InUsePoints inUse)
        {
            var error = ErrorAtPointsInUse.Of(result, inUse);
            string text = error == null ? ErrorAtPointsInUse.Unknown(inUse) : error.Describe();
            return "Estimated " + text + ".";
        }

        private static string Round(double value) => InvariantFormat.Number(Math.Round(value, 4));
    }
}
