using System;
using Lpnn.Probes.Core.Json;
using Lpnn.Probes.Core.Quality;

namespace Lpnn.Probes.Core.Batch
{
    /// <summary>What batch mode reports about a volume's placement besides its probe count (Documentation~/ci.md "Batch
    /// pipeline"): how many of the probes are pinned, and the leak report the inspector shows after Apply
    /// (Documentation~/leaks.md "What is reported") — or why there is none. Written in the batch log line and in the probes
    /// file's <c>source</c>, with the field names `lpnn place` uses where it has them (<c>pinned</c>, <c>leaking</c>).</summary>
    internal sealed class BatchPlacementReport
    {
        /// <summary>Digits the leaking share keeps in the probes file (as `lpnn place` rounds it).</summary>
        public const int ShareDigits = 6;

        /// <summary>Pinned probes among the placed ones (0 when the volume keeps none).</summary>
        public int Pinned { get; }
        /// <summary>The leak report of the placed probes, or null when it could not be made (<see cref="LeaksUnavailable"/>).</summary>
        public LeakReport Leaks { get; }
        /// <summary>Why there is no leak report ("" when there is one).</summary>
        public string LeaksUnavailable { get; }
        /// <summary>Follows the leaking share when the points counted are not the points in use (see <see cref="LeakReport.Sentence"/>).</summary>
        public string CountedNote { get; }

        private BatchPlacementReport(int pinned, LeakReport leaks, string unavailable, string countedNote)
        {
            if (pinned < 0) throw new ArgumentOutOfRangeException(nameof(pinned), pinned, "a count of pinned probes is at least 0");
            Pinned = pinned;
            Leaks = leaks;
            LeaksUnavailable = unavailable;
            CountedNote = countedNote ?? "";
        }

        /// <summary>A placement whose leaks were counted.</summary>
        public static BatchPlacementReport Of(int pinned, LeakReport leaks, string countedNote = "")
        {
            if (leaks == null) throw new ArgumentNullException(nameof(leaks), "no leak report: use WithoutLeaks with the reason");
            return new BatchPlacementReport(pinned, leaks, "", countedNote);
        }

        /// <summary>A placement whose leaks could not be counted (e.g. no lighting for the grid), with the reason.</summary>
        public static BatchPlacementReport WithoutLeaks(int pinned, string reason)
        {
            if (string.IsNullOrEmpty(reason)) throw new ArgumentException("say why the leaks are unavailable", nameof(reason));
            return new BatchPlacementReport(pinned, null, reason, "");
        }

        /// <summary>"3 pinned; Leaks: 12 of 3,456 points in use leak (0.35 %), in 9 tetrahedra" — the inspector's leak line
        /// (without where the Scene view draws the tetrahedra: a batch run has none), or "0 pinned; Leaks unavailable: …".</summary>
        public string Describe() =>
            Pinned + " pinned; " + (Leaks != null ? Leaks.Sentence(CountedNote) : "Leaks unavailable: " + LeaksUnavailable);

        /// <summary>Adds to a probes file's <c>source</c>: <c>pinned</c>; with a report <c>leaking</c> (the share, as `lpnn
        /// place` writes it), <c>leaking_points</c>, <c>leak_points_checked</c> and <c>leaking_tetrahedra</c>; without one
        /// <c>leaks_unavailable</c> (the reason) and no <c>leaking</c>, as `lpnn place` leaves it out when it cannot tell.</summary>
        public void AddTo(JsonValue source)
        {
            if (source == null) throw new ArgumentNullException(nameof(source));
            source.Set("pinned", JsonValue.From(Pinned));
            if (Leaks == null)
            {
                source.Set("leaks_unavailable", JsonValue.From(LeaksUnavailable));
                return;
            }
            source.Set("leaking", JsonValue.From(Math.Round(Leaks.Fraction, ShareDigits)));
            source.Set("leaking_points", JsonValue.From(Leaks.Leaking));
            source.Set("leak_points_checked", JsonValue.From(Leaks.Points));
            source.Set("leaking_tetrahedra", JsonValue.From(Leaks.TetrahedronCount));
        }
    }
}
