using System;
using System.Collections.Generic;
using System.Globalization;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Selection;

namespace Lpnn.Probes.Core.Placement
{
    /// <summary>The pieces of work an inspector button can start whose time grows with the volume's points.</summary>
    internal enum HeavyOperation
    {
        Grid = 0,
        Lighting = 1,
        Features = 2,
        Scoring = 3,
        /// <summary>The whole insertion ranking (Rank by insertion): every point ranked.</summary>
        InsertionRanking = 4,
        /// <summary>The tolerance search's placement-error evaluations (Find probes, Apply with a tolerance).</summary>
        ToleranceSearch = 5,
        /// <summary>Refine in batches (Apply of an insertion method with the option on).</summary>
        BatchedRefinement = 6,
        /// <summary>The insertion rounds Apply and Find probes read, lazily, up to the policy's answer (Quality.InsertionOrder),
        /// with the reference lighting and typical tetrahedron they start from.</summary>
        InsertionRounds = 7,
        /// <summary>Refine in batches avoiding light leaks (Apply of a refined method with Avoid light leaks on, the volume's
        /// default; Documentation~/leaks.md "A leak-aware default"): the leak repair of the seed and the leak-weighted
        /// refinement, their segment casts included.</summary>
        LeakAwareRefinement = 8,
    }

    /// <summary>What a heavy step will cost, and whether the inspector asks before running it.</summary>
    internal readonly struct HeavyEstimate
    {
        /// <summary>Expected seconds from the measured rates of the operations that have one; 0 when none has.</summary>
        public readonly double Seconds;
        /// <summary>Whether every operation has a measured rate (else Seconds covers only some of the work).</summary>
        public readonly bool FullyMeasured;
        /// <summary>Whether some operation's rate leaves out Unity's tetrahedralisations (the whole ranking's, benchmarks.md "The C# core under Mono").</summary>
        public readonly bool ExcludesTetrahedralisations;
        public readonly bool NeedsConfirmation;
        public readonly long Points;

        public HeavyEstimate(long points, double seconds, bool fullyMeasured, bool needsConfirmation, bool excludesTetrahedralisations = false)
        {
            Points = points;
            Seconds = seconds;
            FullyMeasured = fullyMeasured;
            NeedsConfirmation = needsConfirmation;
            ExcludesTetrahedralisations = excludesTetrahedralisations;
        }

        /// <summary>"about 35 s" / "about 6 min" at the rates measured under Mono, with what the figure leaves out; empty when
        /// nothing was measured.</summary>
        public string Describe()
        {
            if (Seconds <= 0) return "";
            var left = new List<string>();
            if (ExcludesTetrahedralisations) left.Add("Unity's tetrahedralisations");
            if (!FullyMeasured) left.Add("the steps without a measured rate");
            return HeavyOperationPolicy.ApproximateTime(Seconds) + " at the rates measured under Mono (Documentation~/benchmarks.md \"The C# core under Mono\")" +
                   (left.Count > 0 ? ", plus " + string.Join(" and ", left) : "");
        }
    }

    /// <summary>One rule for every heavy button: estimate the time from the volume's point count and the rates measured in
    /// Documentation~/benchmarks.md, and ask before anything expected to take more than <see cref="ConfirmAboveSeconds"/>,
    /// or, for steps without a measured rate (they run inside Unity: lighting, rays, inference), before grids larger than
    /// <see cref="LargeGrid"/> points. The same rates give the placement panel's line of Apply's expected time
    /// (<see cref="ApplyLine"/>).</summary>
    internal static class HeavyOperationPolicy
    {
        /// <summary>Points above which a step without a measured rate is confirmed.</summary>
        public const long LargeGrid = 250000;
        /// <summary>Expected seconds above which a step is confirmed (issue 31: "more than ~10 s").</summary>
        public const double ConfirmAboveSeconds = 10.0;

        // ---- The whole insertion ranking (Rank by insertion), benchmarks.md "The C# core under Mono": no C# timing of it exists on real levels
        // (the tests' tetrahedraliser is quadratic), so it is priced from one round given the mesh and excludes Unity's
        // tetrahedralisations.

        /// <summary>Rounds of a whole insertion ranking's work relative to its last round: the prefixes grow by 10 % a round,
        /// so the total is ~11x the last (benchmarks.md "The C# core under Mono").</summary>
        private const double RankingRoundsOfWork = 11.0;
        /// <summary>One insertion round given the mesh, 4.90 s at 10⁶ points, plus the reference lighting (2.48 s) and the
        /// typical tetrahedron (7.45 s) computed once (benchmarks.md "The C# core under Mono", Mono 6.8).</summary>
        private const double RankingSecondsPerPoint = RankingRoundsOfWork * 4.90e-6 + (2.48e-6 + 7.45e-6);

        // ---- What Apply runs, benchmarks.md "The C# core under Mono": the Apply rehearsal of the
        // default (insertion rounds read lazily, the tolerance search at τ = 0.05, the batched refinement) under Mono 6.8,
        // 2026-11-29 on two idle cores (the medians of three runs; the search's evaluations measuring the irradiance mean
        // alone), on two captures of the validation level ctf_compromise;
        // stage wall seconds including the calls to Python's Qhull over a pipe, which stand in for Unity's tetrahedraliser
        // (0.06 s a call at 10⁶ points). Each stage is priced by the line through the two rows (a fixed part
        // — the rounds' count hardly depends on the size — and a part per point).

        /// <summary>ctf_compromise, 136,512 points (benchmarks.md "The C# core under Mono").</summary>
        public const long SmallerMeasuredLevel = 136512;
        /// <summary>ctf_compromise at 0.8128 m, 1,151,667 points (benchmarks.md "The C# core under Mono"): beyond it the rates are extrapolated.</summary>
        public const long LargestMeasuredLevel = 1151667;
        /// <summary>First stage (reference lighting, typical tetrahedron) + insertion rounds: 0.5 + 3.8 s and 4.2 + 29.3 s.</summary>
        private const double RoundsAtSmaller = 0.5 + 3.8, RoundsAtLargest = 4.2 + 29.3;
        /// <summary>The tolerance search's evaluations (18 and 19): 2.5 s and 11.3 s.</summary>
        private const double SearchAtSmaller = 2.5, SearchAtLargest = 11.3;
        /// <summary>The batched refinement (3 tetrahedralisations each, the star refills): 8.4 s and 44.9 s.</summary>
        private const double RefinementAtSmaller = 8.4, RefinementAtLargest = 44.9;
        /// <summary>The leak-aware refinement (the volume's default, Avoid light leaks): the leak repair of the seed plus the
        /// refinement in the C# leak-aware Apply of five validation levels (benchmarks.md "The C# core under Mono", "The
        /// leak-aware Apply": 2026-11-29, Mono 6.8, Python's Qhull over a pipe for Unity's tetrahedraliser and a C# hierarchy
        /// over the level's triangles for Unity's physics, two idle cores, the medians of three runs): q3dm6ish 0.1 + 1.3 s,
        /// fan 0.3 + 3.7 s, oa_koth1 0.8 + 10.0 s, ctf_compromise 2.4 + 26.4 s and at 0.8128 m 17.5 + 190.9 s. Priced through
        /// all five (linearly between them, in proportion below the smallest, along the last segment beyond the largest): a
        /// line through the two large levels alone would charge its intercept to every small volume, where q3dm6ish's took
        /// 1.4 s.</summary>
        private static readonly long[] LeakAwarePoints = { 2100, 6940, 41931, SmallerMeasuredLevel, LargestMeasuredLevel };
        private static readonly double[] LeakAwareSeconds = { 0.1 + 1.3, 0.3 + 3.7, 0.8 + 10.0, 2.4 + 26.4, 17.5 + 190.9 };

        private static double PerPoint(double atSmaller, double atLargest) => (atLargest - atSmaller) / (LargestMeasuredLevel - SmallerMeasuredLevel);
        private static double Fixed(double atSmaller, double atLargest) => atSmaller - PerPoint(atSmaller, atLargest) * SmallerMeasuredLevel;

        /// <summary>Expected seconds of a measured operation on <paramref name="points"/> (> 0) points.</summary>
        private static double Seconds(HeavyOperation operation, long points)
        {
            if (operation != HeavyOperation.LeakAwareRefinement) return Math.Max(0, FixedSeconds(operation) + SecondsPerPoint(operation) * points);
            if (points <= LeakAwarePoints[0]) return LeakAwareSeconds[0] * points / LeakAwarePoints[0];
            int above = 1;
            while (above < LeakAwarePoints.Length - 1 && points > LeakAwarePoints[above]) above++;
            return LeakAwareSeconds[above - 1] + LeakAwareSlope(above) * (points - LeakAwarePoints[above - 1]);
        }

        /// <summary>Seconds per point of the leak-aware refinement between its measured levels <paramref name="upper"/> - 1 and <paramref name="upper"/>.</summary>
        private static double LeakAwareSlope(int upper) =>
            (LeakAwareSeconds[upper] - LeakAwareSeconds[upper - 1]) / (LeakAwarePoints[upper] - LeakAwarePoints[upper - 1]);

        /// <summary>Seconds per point of one operation under Mono (the leak-aware refinement's beyond its largest measured
        /// level), or NaN when only Unity can measure it.</summary>
        public static double SecondsPerPoint(HeavyOperation operation)
        {
            switch (operation)
            {
                case HeavyOperation.InsertionRanking: return RankingSecondsPerPoint;
                case HeavyOperation.InsertionRounds: return PerPoint(RoundsAtSmaller, RoundsAtLargest);
                case HeavyOperation.ToleranceSearch: return PerPoint(SearchAtSmaller, SearchAtLargest);
                case HeavyOperation.BatchedRefinement: return PerPoint(RefinementAtSmaller, RefinementAtLargest);
                case HeavyOperation.LeakAwareRefinement: return LeakAwareSlope(LeakAwarePoints.Length - 1);
                case HeavyOperation.Grid:
                case HeavyOperation.Lighting:
                case HeavyOperation.Features:
                case HeavyOperation.Scoring:
                    return double.NaN;
                default:
                    throw new ArgumentOutOfRangeException(nameof(operation), operation, "not a heavy operation");
            }
        }

        /// <summary>Seconds an operation priced by a line costs whatever the size (its rounds); 0 for those priced per point
        /// alone, through their measured levels (the leak-aware refinement) or unmeasured.</summary>
        public static double FixedSeconds(HeavyOperation operation)
        {
            switch (operation)
            {
                case HeavyOperation.InsertionRounds: return Fixed(RoundsAtSmaller, RoundsAtLargest);
                case HeavyOperation.ToleranceSearch: return Fixed(SearchAtSmaller, SearchAtLargest);
                case HeavyOperation.BatchedRefinement: return Fixed(RefinementAtSmaller, RefinementAtLargest);
                default:
                    SecondsPerPoint(operation);  // names an unknown operation
                    return 0;
            }
        }

        /// <summary>The estimate of running <paramref name="operations"/> one after another on <paramref name="points"/> points
        /// (no time at all on an empty grid).</summary>
        public static HeavyEstimate Estimate(long points, IEnumerable<HeavyOperation> operations)
        {
            if (points < 0) throw new LpnnException("the point count is " + points + "; it cannot be negative");
            if (operations == null) throw new ArgumentNullException(nameof(operations));
            double seconds = 0;
            bool fullyMeasured = true, anyUnmeasured = false, excludesTetrahedralisations = false;
            foreach (var operation in operations)
            {
                double rate = SecondsPerPoint(operation);
                if (double.IsNaN(rate)) { fullyMeasured = false; anyUnmeasured = true; }
                else if (points > 0) seconds += Seconds(operation, points);
                if (operation == HeavyOperation.InsertionRanking) excludesTetrahedralisations = true;
            }
            bool confirm = seconds > ConfirmAboveSeconds || (anyUnmeasured && points > LargeGrid);
            return new HeavyEstimate(points, seconds, fullyMeasured, confirm, excludesTetrahedralisations);
        }

        /// <summary>What Apply (or Find probes, <paramref name="searchOnly"/>) runs for a placement by <paramref name="method"/>:
        /// insertion methods read the insertion rounds up to the answer (none when the whole ranking is already known,
        /// <paramref name="rankingKnown"/>), a tolerance policy searches, and the refined methods refine in batches — avoiding
        /// light leaks when the volume does (<paramref name="avoidLeaks"/>, its Avoid light leaks; the leak-blind refinement
        /// otherwise).</summary>
        public static List<HeavyOperation> PlacementOperations(PlacementMethod method, bool tolerance, bool searchOnly, bool avoidLeaks,
            bool rankingKnown = false)
        {
            var operations = new List<HeavyOperation>();
            if (PlacementMethods.RanksByInsertion(method) && !rankingKnown) operations.Add(HeavyOperation.InsertionRounds);
            if (tolerance) operations.Add(HeavyOperation.ToleranceSearch);
            if (PlacementMethods.RefinesInBatches(method) && !searchOnly)
                operations.Add(avoidLeaks ? HeavyOperation.LeakAwareRefinement : HeavyOperation.BatchedRefinement);
            return operations;
        }

        /// <summary>"under a second", "about 7 s" (whole seconds up to 10 s, rounded up), "about 35 s" (to 5 s below 90 s),
        /// "about 4 min" (whole minutes below 90 min), "about 2.5 h".</summary>
        public static string ApproximateTime(double seconds)
        {
            if (double.IsNaN(seconds) || seconds < 0) throw new ArgumentOutOfRangeException(nameof(seconds), seconds, "not a duration");
            var culture = CultureInfo.InvariantCulture;
            if (seconds < 1) return "under a second";
            if (seconds < 10) return "about " + Math.Ceiling(seconds).ToString(culture) + " s";
            if (seconds < 90) return "about " + (5 * Math.Max(2, Math.Round(seconds / 5, MidpointRounding.AwayFromZero))).ToString(culture) + " s";
            if (seconds < 90 * 60) return "about " + Math.Max(2, Math.Round(seconds / 60, MidpointRounding.AwayFromZero)).ToString(culture) + " min";
            return "about " + Math.Round(seconds / 3600, 1, MidpointRounding.AwayFromZero).ToString("0.0", culture) + " h";
        }

        /// <summary>The placement panel's line of what Apply will cost for the volume's <paramref name="points"/>, shown before
        /// Apply is pressed: e.g. "Apply: about 15 s for 136,512 points (insertion rounds, the tolerance search and the
        /// refinement in batches; C# rates measured under Mono on real levels, Documentation~/benchmarks.md "The C# core under Mono")".
        /// <paramref name="previewKnown"/>: Apply writes the preview's selection as it is (no refinement).
        /// <paramref name="avoidLeaks"/>: the volume's Avoid light leaks — a refined method's refinement then avoids leaks, is
        /// priced as such, and the line says so.</summary>
        public static string ApplyLine(long points, PlacementMethod method, SelectionPolicy policy, bool rankingKnown, bool previewKnown, bool avoidLeaks)
        {
            if (points <= 0) return "Apply: its expected time shows once the grid is built.";
            string count = " for " + InvariantFormat.Count(points) + " points";
            if (previewKnown) return "Apply: under a second" + count + " (it writes the selection shown above).";
            bool byInsertion = PlacementMethods.RanksByInsertion(method);
            var operations = PlacementOperations(method, policy == SelectionPolicy.Tolerance, false, avoidLeaks, rankingKnown);
            if (operations.Count == 0)
                return "Apply: no insertion rounds, tolerance search or refinement to wait for" + count + " (it ranks the stored scores).";
            var estimate = Estimate(points, operations);
            var steps = new List<string>();
            foreach (var operation in operations) steps.Add(StepName(operation, method));
            var notes = new List<string>();
            if (byInsertion && !rankingKnown && policy != SelectionPolicy.Tolerance)
                notes.Add("measured at τ = 0.05: a budget of many probes takes more rounds");
            if (PlacementMethods.GuidesInsertion(method) && !rankingKnown) notes.Add("guided rounds priced as plain insertion's");
            if (points > LargestMeasuredLevel)
                notes.Add("extrapolated beyond the " + InvariantFormat.Count(LargestMeasuredLevel) + " points measured");
            bool leakAware = operations.Contains(HeavyOperation.LeakAwareRefinement);
            return "Apply: " + ApproximateTime(estimate.Seconds) + count + " (" + JoinSteps(steps) +
                   "; C# rates measured under Mono on real levels, Python's Qhull standing in for Unity's tetrahedraliser" +
                   (leakAware ? " and a C# ray hierarchy for Unity's physics" : "") + ", " +
                   "Documentation~/benchmarks.md \"The C# core under Mono\"" + (notes.Count > 0 ? "; " + string.Join("; ", notes) : "") + ").";
        }

        private static string StepName(HeavyOperation operation, PlacementMethod method)
        {
            switch (operation)
            {
                case HeavyOperation.InsertionRounds: return PlacementMethods.GuidesInsertion(method) ? "guided insertion rounds" : "insertion rounds";
                case HeavyOperation.ToleranceSearch: return "the tolerance search";
                case HeavyOperation.BatchedRefinement: return "the refinement in batches";
                case HeavyOperation.LeakAwareRefinement: return "the refinement in batches avoiding light leaks";
                case HeavyOperation.InsertionRanking: return "the whole insertion ranking";
                default: return operation.ToString().ToLowerInvariant();
            }
        }

        private static string JoinSteps(List<string> steps) =>
            steps.Count == 1 ? steps[0] : string.Join(", ", steps.GetRange(0, steps.Count - 1)) + " and " + steps[steps.Count - 1];
    }
}
