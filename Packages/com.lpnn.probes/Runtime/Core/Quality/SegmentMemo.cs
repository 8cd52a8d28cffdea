using System;

namespace Lpnn.Probes.Core.Quality
{
    /// <summary>Whether an evaluation point sees another (the segment test of <see cref="LeakCheck"/>), remembered for each
    /// point's <see cref="DefaultSlots"/> most recently tested partners: the leak repair and batched refinement ask the same
    /// point-probe segments round after round (a point's new stencil usually shares 3 of its 4 probes with the old one),
    /// and a segment's visibility never changes, so the answers are those of casting it anew with fewer rays. One per
    /// placement (<see cref="LeakWeighting"/>); slots are replaced per point in turn, so the rays cast are deterministic.
    /// Port of lpnn/quality/metric/leak_rule.py SegmentVisibility (Documentation~/leaks.md).</summary>
    internal sealed class SegmentMemo
    {
        /// <summary>Partners remembered per point: a stencil (4) and a trial's (lpnn/quality/metric/leak_rule.py MEMO_SLOTS).</summary>
        public const int DefaultSlots = 8;

        private readonly int slots;
        private readonly int[] partner;  // slots per point; -1: empty
        private readonly bool[] sees;
        private readonly byte[] next;  // the slot a point's next new partner overwrites

        /// <summary>The points' count this memo is for (one per evaluation point of a <see cref="ReferenceLighting"/>).</summary>
        public int PointCount { get; }

        /// <summary>Segments looked up, and of them remembered (not cast again): the memo's effect, for tests and benchmarks.</summary>
        public long Asked { get; private set; }
        public long Known { get; private set; }

        public SegmentMemo(int pointCount, int slots = DefaultSlots)
        {
            if (pointCount < 0) throw new ArgumentOutOfRangeException(nameof(pointCount), pointCount, "must be >= 0");
            if (slots < 4 || slots > byte.MaxValue)
                throw new ArgumentOutOfRangeException(nameof(slots), slots, "at least a whole stencil (4), at most 255");
            this.slots = slots;
            PointCount = pointCount;
            partner = new int[checked(pointCount * slots)];
            sees = new bool[pointCount * slots];
            next = new byte[pointCount];
            for (int i = 0; i < partner.Length; i++) partner[i] = -1;
        }

        /// <summary>Whether the segment from <paramref name="point"/> to <paramref name="other"/> is remembered, and then
        /// whether it is <paramref name="free"/>.</summary>
        public bool TryGet(int point, int other, out bool free)
        {
            Asked++;
            int row = point * slots;
            for (int s = 0; s < slots; s++)
                if (partner[row + s] == other)
                {
                    Known++;
                    free = sees[row + s];
                    return true;
                }
            free = false;
            return false;
        }

        /// <summary>Remembers a cast segment in <paramref name="point"/>'s next slot (its oldest partner goes).</summary>
        public void Remember(int point, int other, bool free)
        {
            int slot = point * slots + next[point];
            partner[slot] = other;
            sees[slot] = free;
            next[point] = (byte)((next[point] + 1) % slots);
        }
    }
}
