using System;
using System.Collections.Generic;
using System.Globalization;

namespace Lpnn.Probes.Core.Placement
{
    /// <summary>The pieces of work an inspector button can start whose time grows with the volume's points.</summary>
    internal enum HeavyOperation
    {
        Grid = 0,
        Lighting = 1,
        Features = 2,
        Scoring = 3,
        /// <summary>The whole insertion ranking (Rank by insertion).</summary>
        InsertionRanking = 4,
        /// <summary>The tolerance search's placement-error evaluations (Find probes, Apply with a tolerance).</summary>
        ToleranceSearch = 5,
        /// <summary>Refine in batches (Apply of an insertion method with the option on).</summary>
        BatchedRefinement = 6,
    }

    /// <summary>What a heavy step will cost, and whether the inspector asks before running it.</summary>
    internal readonly struct HeavyEstimate
    {
        /// <summary>Expected seconds from the measured rates of the operations that have one; 0 when none has.</summary>
        public readonly double Seconds;
        /// <summary>Whether every operation has a measured rate (else Seconds covers only some of the work).</summary>
        public readonly bool FullyMeasured;
        public readonly bool NeedsConfirmation;
        public readonly long Points;

        public HeavyEstimate(long points, double seconds, bool fullyMeasured, bool needsConfirmation)
        {
            Points = points;
            Seconds = seconds;
            FullyMeasured = fullyMeasured;
            NeedsConfirmation = needsConfirmation;
        }

        /// <summary>"about 37 s" / "about 6 min", with what the figure leaves out; empty when nothing was measured.</summary>
        public string Describe()
        {
            if (Seconds <= 0) return "";
            string time = Seconds < 90
                ? Math.Ceiling(Seconds).ToString(CultureInfo.InvariantCulture) + " s"
                : Math.Ceiling(Seconds / 60).ToString(CultureInfo.InvariantCulture) + " min";
            return "about " + time + " of C# work at the rates measured under Mono (Documentation~/benchmarks.md §7.4, §11.3), " +
                   "plus Unity's tetrahedralisations" + (FullyMeasured ? "" : " and the steps without a measured rate");
        }
    }

    /// <summary>One rule for every heavy button: estimate the time from the volume's point count and the rates measured in
    /// Documentation~/benchmarks.md, and ask before anything expected to take more than <see cref="ConfirmAboveSeconds"/>,
    /// or, for steps without a measured rate (they run inside Unity: lighting, rays, inference), before grids larger than
    /// <see cref="LargeGrid"/> points.</summary>
    internal static class HeavyOperationPolicy
    {
        /// <summary>Points above which a step without a measured rate is confirmed.</summary>
        public const long LargeGrid = 250000;
        /// <summary>Expected seconds above which a step is confirmed (issue 31: "more than ~10 s").</summary>
        public const double ConfirmAboveSeconds = 10.0;

        /// <summary>Rounds of a whole insertion ranking's work relative to its last round: the prefixes grow by 10 % a round,
        /// so the total is ~11x the last (benchmarks.md §7.4).</summary>
        private const double RankingRoundsOfWork = 11.0;
        /// <summary>One insertion round given the mesh, 4.90 s at 10⁶ points, plus the reference lighting (2.48 s) and the
        /// typical tetrahedron (7.45 s) computed once (benchmarks.md §7.4, Mono 6.8).</summary>
        private const double RankingSecondsPerPoint = RankingRoundsOfWork * 4.90e-6 + (2.48e-6 + 7.45e-6);
        /// <summary>One batched-refinement round, 2.49 s at 10⁶ points (benchmarks.md §11.3, Mono), times the 150 rounds a
        /// whole level takes at most (§11.2: 90–150).</summary>
        private const double RefinementSecondsPerPoint = 150 * 2.49e-6;
        /// <summary>The tolerance search's evaluations of every point (ToleranceSearch: at most 2·log₂N + 2; 18–30 measured in
        /// §7.4), each priced as one refinement round's pass over the points (§11.3), an upper bound.</summary>
        private const double SearchEvaluations = 30;
        private const double SearchSecondsPerPoint = SearchEvaluations * 2.49e-6;

        /// <summary>Seconds per point of one operation under Mono, or NaN when only Unity can measure it.</summary>
        public static double SecondsPerPoint(HeavyOperation operation)
        {
            switch (operation)
            {
                case HeavyOperation.InsertionRanking: return RankingSecondsPerPoint;
                case HeavyOperation.ToleranceSearch: return SearchSecondsPerPoint;
                case HeavyOperation.BatchedRefinement: return RefinementSecondsPerPoint;
                case HeavyOperation.Grid:
                case HeavyOperation.Lighting:
                case HeavyOperation.Features:
                case HeavyOperation.Scoring:
                    return double.NaN;
                default:
                    throw new ArgumentOutOfRangeException(nameof(operation), operation, "not a heavy operation");
            }
        }

        /// <summary>The estimate of running <paramref name="operations"/> one after another on <paramref name="points"/> points.</summary>
        public static HeavyEstimate Estimate(long points, IEnumerable<HeavyOperation> operations)
        {
            if (points < 0) throw new LpnnException("the point count is " + points + "; it cannot be negative");
            if (operations == null) throw new ArgumentNullException(nameof(operations));
            double seconds = 0;
            bool fullyMeasured = true, anyUnmeasured = false;
            foreach (var operation in operations)
            {
                double rate = SecondsPerPoint(operation);
                if (double.IsNaN(rate)) { fullyMeasured = false; anyUnmeasured = true; }
                else seconds += rate * points;
            }
            bool confirm = seconds > ConfirmAboveSeconds || (anyUnmeasured && points > LargeGrid);
            return new HeavyEstimate(points, seconds, fullyMeasured, confirm);
        }

        /// <summary>What Apply (or Find probes, <paramref name="searchOnly"/>) runs for a placement: insertion methods rank
        /// (lazily on Apply, but up to the whole ranking), a tolerance policy searches, and Refine in batches refines.</summary>
        public static List<HeavyOperation> PlacementOperations(bool byInsertion, bool tolerance, bool refineInBatches, bool searchOnly)
        {
            var operations = new List<HeavyOperation>();
            if (byInsertion) operations.Add(HeavyOperation.InsertionRanking);
            if (tolerance) operations.Add(HeavyOperation.ToleranceSearch);
            if (byInsertion && refineInBatches && !searchOnly) operations.Add(HeavyOperation.BatchedRefinement);
            return operations;
        }
    }
}
