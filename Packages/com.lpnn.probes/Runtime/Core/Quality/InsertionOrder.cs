using System;
using System.Collections.Generic;
using System.Threading;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Selection;
using Lpnn.Probes.Core.Sh;

namespace Lpnn.Probes.Core.Quality
{
    /// <summary>The insertion ranking (<see cref="InsertionRanking"/>) computed only as far as it is read: <see cref="Prefix"/>
    /// runs rounds until the points asked for are ranked. A budget of K points, or the tolerance policy's search (exponential
    /// from 4, then bisection: it never reads beyond about twice its answer), thus costs the rounds up to that count instead
    /// of the ~log(N / 4) / log(1 + growth) rounds of the whole ranking; the prefixes are those of the whole ranking exactly
    /// (the same rounds, in the same order). Port of lpnn/quality/placement/insertion.py InsertionOrder (quality.md §5.1 step 4); with
    /// a guide, guided insertion (quality.md §5.2). Each round after the first locates only the points whose tetrahedron
    /// the last insertion broke, and those outside the hull (<see cref="InsertionRounds"/>, quality.md §5.1 step 5).</summary>
    public sealed class InsertionOrder
    {
        private const string Stage = "insertion ranking";

        private readonly ReferenceLighting _reference;
        private readonly double _growth;
        /// <summary>Guided insertion's weight of each of the reference's points (null: plain insertion).</summary>
        private readonly double[] _guide;
        /// <summary>The grid index of each ranked point (null: the reference's points are the grid's).</summary>
        private readonly int[] _rows;
        private readonly List<int> _order;
        private readonly bool[] _chosen;
        /// <summary>Null, or one flag per point of the reference: only these may be ranked (pinned probes, pins.md).</summary>
        private readonly bool[] _candidates;
        /// <summary>The rounds, located incrementally: a point whose tetrahedron survived the last insertion keeps it
        /// (quality.md §5.1 step 5).</summary>
        private readonly InsertionRounds _rounds = new InsertionRounds();
        /// <summary>Each round's tetrahedra: the tetrahedraliser's, or (opt-in) derived from the last round's by insertion.</summary>
        private readonly InsertionTetrahedra _tetrahedra;
        /// <summary>Every point not yet ranked is interpolated exactly: the rest follow by index.</summary>
        private bool _exhausted;

        /// <summary>Points this order ranks (the valid ones for <see cref="OfValid"/>).</summary>
        public int Count => _reference.Count;
        /// <summary>Points ranked so far.</summary>
        public int Ranked => _order.Count;
        public bool IsComplete => _order.Count == _reference.Count;
        /// <summary>Insertion rounds run so far.</summary>
        public int Rounds { get; private set; }

        /// <param name="reference">The dense lighting of exactly this grid's points.</param>
        /// <param name="tetrahedralizer">Unity's in the editor; tests use a Delaunay of their own.</param>
        /// <param name="growth">Fraction of the current probes inserted per round (&gt; 0).</param>
        /// <param name="guide">Null (plain insertion), or one weight per point of <paramref name="reference"/>, each finite and
        /// &gt; 0 (<see cref="InsertionRanking.GuideWeights"/> of their scores): guided insertion (quality.md §5.2). Copied.</param>
        public InsertionOrder(EvaluationGrid grid, ReferenceLighting reference, ITetrahedralizer tetrahedralizer, double growth = InsertionRanking.DefaultGrowth,
            double[] guide = null)
            : this(grid, reference, tetrahedralizer, growth, guide == null ? null : (double[])guide.Clone(), null, null)
        {
        }

        /// <param name="guide">Owned by this order (not copied).</param>
        /// <param name="pins">Null, or pins snapped to <paramref name="grid"/>'s own points: the order starts with them (then the
        /// usual start without the blocked points) and never ranks a blocked point (pins.md).</param>
        private InsertionOrder(EvaluationGrid grid, ReferenceLighting reference, ITetrahedralizer tetrahedralizer, double growth, double[] guide, int[] rows,
            Pins pins)
        {
            if (tetrahedralizer == null) throw new ArgumentNullException(nameof(tetrahedralizer));
            if (reference == null) throw new ArgumentNullException(nameof(reference));
            InsertionRanking.CheckGrowth(growth);
            InsertionRanking.CheckGuide(guide, reference.Count);
            int[] start = InsertionRanking.Start(grid, reference);
            if (pins != null)
            {
                start = Pins.Start(grid, pins.Indices, pins.Blocked, start);
                _candidates = new bool[reference.Count];
                for (int n = 0; n < _candidates.Length; n++) _candidates[n] = !pins.Blocked[n];
            }
            _reference = reference;
            _tetrahedra = new InsertionTetrahedra(reference, tetrahedralizer);
            _growth = growth;
            _guide = guide;
            _rows = rows;
            _order = new List<int>(start);
            _chosen = new bool[reference.Count];
            foreach (int p in start) _chosen[p] = true;
        }

        /// <summary>The insertion order of the valid points alone, as `lpnn place` ranks a capture whose points inside
        /// geometry were dropped (invalid points neither become probes nor steer the rounds); it ranks grid indices of valid
        /// points only. With scores, guided insertion (quality.md §5.2) as `lpnn place --guided` does it: the valid points'
        /// scores alone make the weights (<see cref="InsertionRanking.GuideWeights"/>, so the median is theirs; the scores of
        /// invalid points, e.g. the Scoring step's 0, are never read).</summary>
        /// <param name="sh">27 floats per grid point (Documentation~/sh.md).</param>
        /// <param name="sceneScale">The whole grid's scene scale, so the errors are those of the full reference.</param>
        /// <param name="valid">One flag per grid point, or null (all valid).</param>
        /// <param name="scores">One network score per grid point (guided insertion), or null (plain insertion).</param>
        public static InsertionOrder OfValid(EvaluationGrid grid, float[] sh, double sceneScale, bool[] valid, ITetrahedralizer tetrahedralizer,
            double growth = InsertionRanking.DefaultGrowth, float[] scores = null) =>
            OfValid(grid, sh, sceneScale, valid, tetrahedralizer, null, growth, scores);

        /// <summary>As the public overload, with <paramref name="pins"/> (null: none) snapped to <paramref name="grid"/> with the
        /// same <paramref name="valid"/> flags (<see cref="Pins.Snap"/>): the pins come first and no point near one is ranked.</summary>
        internal static InsertionOrder OfValid(EvaluationGrid grid, float[] sh, double sceneScale, bool[] valid, ITetrahedralizer tetrahedralizer, Pins pins,
            double growth = InsertionRanking.DefaultGrowth, float[] scores = null)
        {
            if (grid == null) throw new ArgumentNullException(nameof(grid));
            if (sh == null) throw new ArgumentNullException(nameof(sh));
            if (valid == null)
                return new InsertionOrder(grid, ReferenceLighting.FromGrid(grid, sh, sceneScale), tetrahedralizer, growth,
                    InsertionRanking.GuideOf(scores, grid.Count), null, pins);
            int validCount = ValidCandidates.Check(grid, valid);
            if (sh.Length != ShMath.FloatsPerProbe * grid.Count)
                throw new PlacementErrorException("need 27 SH coefficients per evaluation point: got " + InvariantFormat.Count(sh.Length) +
                                                  " values for " + InvariantFormat.Count(grid.Count) + " points");
            InsertionRanking.CheckScoreCount(scores, grid.Count);  // the weights are the valid points' (below)
            var rows = new int[validCount];
            var validSh = new float[ShMath.FloatsPerProbe * validCount];
            var validScores = scores == null ? null : new float[validCount];
            for (int n = 0, m = 0; n < grid.Count; n++)
            {
                if (!valid[n]) continue;
                Array.Copy(sh, ShMath.FloatsPerProbe * n, validSh, ShMath.FloatsPerProbe * m, ShMath.FloatsPerProbe);
                if (validScores != null) validScores[m] = scores[n];
                rows[m++] = n;
            }
            var validGrid = grid.Subset(valid);
            return new InsertionOrder(validGrid, ReferenceLighting.FromGrid(validGrid, validSh, sceneScale), tetrahedralizer, growth,
                InsertionRanking.GuideOf(validScores, validCount), rows, pins == null ? null : pins.OfRows(rows));
        }

        /// <summary>The ranking's first min(<paramref name="count"/>, <see cref="Count"/>) points — or more: every point
        /// ranked so far, in order (grid indices). Always at least the starting tetrahedron, which spans a volume.</summary>
        /// <param name="progress">Called before every round with the points ranked so far, of the count asked for.</param>
        public int[] Prefix(int count, ProgressCallback progress = null, CancellationToken cancel = default)
        {
            count = Math.Max(0, Math.Min(count, Count));
            if (_order.Count < count)
            {
                while (_order.Count < count && !_exhausted)
                {
                    progress?.Invoke(Stage, _order.Count, count);
                    cancel.ThrowIfCancellationRequested();  // after the call, where the editor reads its Cancel button: no round starts
                    int[] probes = _order.ToArray();
                    int[] batch = _rounds.NextBatch(_reference, probes, _tetrahedra.Of(probes), _growth, _guide, _candidates);
                    Rounds++;
                    if (batch.Length == 0) _exhausted = true;
                    foreach (int p in batch)
                    {
                        _order.Add(p);
                        _chosen[p] = true;
                    }
                }
                if (_order.Count < count)
                    for (int n = 0; n < _chosen.Length; n++)
                        if (!_chosen[n] && (_candidates == null || _candidates[n])) _order.Add(n);
                progress?.Invoke(Stage, count, count);
                cancel.ThrowIfCancellationRequested();
            }
            var ranked = new int[_order.Count];
            for (int r = 0; r < ranked.Length; r++) ranked[r] = _rows == null ? _order[r] : _rows[_order[r]];
            return ranked;
        }

        /// <summary>Every point once, most important first.</summary>
        public int[] All(ProgressCallback progress = null, CancellationToken cancel = default) => Prefix(Count, progress, cancel);

        /// <summary>Rounds whose tetrahedra were derived, and tetrahedralisations made (tests and the Apply bench).</summary>
        internal InsertionTetrahedra Tetrahedra => _tetrahedra;
    }
}
