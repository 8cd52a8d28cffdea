using System;
using System.Collections.Generic;
using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Core.Selection
{
    /// <summary>What the tolerance search found: the prefix count it settled on, that count's error, and every count it
    /// evaluated with its error (ascending).</summary>
    public sealed class ToleranceSearchResult
    {
        public int Count { get; }
        public double MeanError { get; }
        public IReadOnlyList<KeyValuePair<int, double>> Evaluated { get; }

        public ToleranceSearchResult(int count, double meanError, IReadOnlyList<KeyValuePair<int, double>> evaluated)
        {
            Count = count;
            MeanError = meanError;
            Evaluated = evaluated;
        }
    }

    /// <summary>The search of Documentation~/quality.md §4: the smallest prefix of a ranking whose mean error is ≤ τ.
    /// The error is not monotonic in the count (a new probe re-tetrahedralises its neighbourhood), so the search
    /// guarantees what it checks: exponential search from the smallest count (4, 8, 16, …, N), then bisection between
    /// the last failing and the first passing count until they are adjacent or at most count / <see cref="Resolution"/>
    /// apart. The returned count passed; every smaller evaluated count failed; a failing one lies within
    /// max(1, count / Resolution) below it (unless it is the smallest count); at most 2·log₂N + 2 evaluations.</summary>
    internal static class ToleranceSearch
    {
        /// <summary>Unity needs 4 probes for a tetrahedron, so smaller prefixes are never worth evaluating.</summary>
        public const int SmallestCount = 4;

        /// <summary>The bisection stops at 1/256 of the passing count: at most 1/256 more probes than a search to the
        /// unit (within the error's own non-monotonic noise) for about 8 fewer evaluations on large answers, each a
        /// tetrahedralisation and a pass over every point; answers below 256 are found to the unit. Python:
        /// lpnn.quality.placement.policy_rules.SEARCH_RESOLUTION.</summary>
        public const int Resolution = 256;

        /// <param name="pointCount">N, the longest prefix (all points: error 0).</param>
        /// <param name="errorAtCount">Mean error of the selection made from the first <c>count</c> ranked points.</param>
        /// <param name="tolerance">τ &gt; 0.</param>
        public static ToleranceSearchResult Run(int pointCount, Func<int, double> errorAtCount, double tolerance)
        {
            if (errorAtCount == null) throw new ArgumentNullException(nameof(errorAtCount));
            if (!(tolerance > 0) || double.IsInfinity(tolerance))
                throw new SelectionException("tolerance " + InvariantFormat.Number(tolerance) + " must be a mean error greater than 0 (e.g. 0.02)");
            if (pointCount < 1) throw new SelectionException("there are no evaluation points to place probes at");
            var evaluated = new SortedDictionary<int, double>();
            Func<int, double> error = count =>
            {
                if (!evaluated.TryGetValue(count, out double e))
                {
                    e = errorAtCount(count);
                    if (double.IsNaN(e)) throw new SelectionException("the placement error of " + count + " probes is not a number");
                    evaluated[count] = e;
                }
                return e;
            };

            int smallest = Math.Min(SmallestCount, pointCount);
            int failing = smallest - 1, passing = smallest;
            while (error(passing) > tolerance)
            {
                if (passing == pointCount)
                    throw new SelectionException("even all " + InvariantFormat.Count(pointCount) + " points miss the tolerance " +
                                                 InvariantFormat.Number(tolerance) + "; use a larger tolerance");
                failing = passing;
                passing = (int)Math.Min(2L * passing, pointCount);
            }
            while (!Resolved(failing, passing))
            {
                int middle = failing + (passing - failing) / 2;
                if (error(middle) <= tolerance) passing = middle;
                else failing = middle;
            }
            return new ToleranceSearchResult(passing, evaluated[passing], new List<KeyValuePair<int, double>>(evaluated));
        }

        /// <summary>Whether the bisection may stop: the last failing and the first passing count are adjacent or at most
        /// passing / <see cref="Resolution"/> apart (integer arithmetic, as Python's policies.search_resolved).</summary>
        internal static bool Resolved(int failing, int passing)
        {
            long width = (long)passing - failing;
            return width <= 1 || width * Resolution <= passing;
        }
    }
}
