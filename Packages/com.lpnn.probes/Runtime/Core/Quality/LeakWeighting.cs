using System;
using System.Collections.Generic;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Core.Quality
{
    /// <summary>The leak-aware option of batched refinement (Documentation~/leaks.md "A leak-aware default"): the error of
    /// every point that leaks (<see cref="LeakCheck"/>) counts <see cref="Weight"/> times, in the removal costs, the
    /// tolerance and the error sum alike, so a removal that lets a stencil reach through a wall is taken only when it is
    /// cheap anyway. Only the error is weighted: a leak that changes nothing costs nothing. Port of
    /// lpnn/quality/placement/leak_aware.py LeakWeighting; parity pinned by Tests/Data/leak_aware_golden.json.</summary>
    internal sealed class LeakWeighting
    {
        /// <summary>A leaking point's error counts this many times (lpnn/quality/placement/leak_aware.py LEAK_WEIGHT; benchmarks.md "Light leaks"
        /// measured 2, 4, 8 and 16).</summary>
        public const double DefaultWeight = 8.0;

        public IRaycaster Raycaster { get; }
        public double Weight { get; }

        private SegmentMemo memo;
        private ReferenceLighting memoReference;

        /// <param name="raycaster">The scene's rays (Unity's physics in the editor), for the segment test of the leak rule.</param>
        /// <param name="weight">At least 1 (1: leaks count as any error).</param>
        /// <param name="remember">Whether segments are remembered (<see cref="MemoFor"/>); false casts every segment anew — the
        /// same answers with more rays, which the Apply benchmark times (benchmarks.md "The C# core under Mono").</param>
        public LeakWeighting(IRaycaster raycaster, double weight = DefaultWeight, bool remember = true)
        {
            Raycaster = raycaster ?? throw new ArgumentNullException(nameof(raycaster));
            if (!(weight >= 1.0) || double.IsInfinity(weight))
                throw new PlacementErrorException("leak weight " + InvariantFormat.Number(weight) + " must be a finite number >= 1 (1: leaks count as any error; " +
                                                  InvariantFormat.Number(DefaultWeight) + " is recommended)");
            Weight = weight;
            Remembers = remember;
        }

        /// <summary>Whether the segments cast are remembered for the placement (the default), or cast anew each time.</summary>
        public bool Remembers { get; }

        /// <summary>The segments between <paramref name="reference"/>'s points this weighting has cast, remembered
        /// (<see cref="SegmentMemo"/>; a new memo for another reference): the leak repair of the seed shares it with the
        /// refinement, so a placement casts each segment about once. Null when this weighting does not remember
        /// (<see cref="Remembers"/>).</summary>
        internal SegmentMemo MemoFor(ReferenceLighting reference)
        {
            if (reference == null) throw new ArgumentNullException(nameof(reference));
            if (!Remembers) return null;
            if (!ReferenceEquals(reference, memoReference))
            {
                memo = new SegmentMemo(reference.Count);
                memoReference = reference;
            }
            return memo;
        }

        /// <summary>Multiplies by <see cref="Weight"/> the <paramref name="errors"/> (indexed by point) of the points
        /// <paramref name="visited"/> that leak through their stencils (probe-list indices into <paramref name="probes"/>).</summary>
        internal void Weigh(ReferenceLighting reference, int[] probes, StencilLog visited, double[] errors)
        {
            bool[] leaking = LeakCheck.Leaking(reference, probes, visited.Points, visited.Stencils, Raycaster, MemoFor(reference));
            for (int i = 0; i < visited.Count; i++)
                if (leaking[i]) errors[visited.Points[i]] *= Weight;
        }
    }
}
