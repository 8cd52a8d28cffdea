using System;
using System.Collections.Generic;
using System.Numerics;
using System.Threading;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Selection;
using Lpnn.Probes.Core.Sh;

namespace Lpnn.Probes.Core.Quality
{
    /// <summary>Error-driven insertion (Documentation~/quality.md §5), the best non-learned placement we measured: from a
    /// "typical" tetrahedron and the grid's extreme points (<see cref="Start"/>), interpolate every point from the current probes and insert, per round, the worst point of
    /// each tetrahedron, the cells with the largest summed error first, up to ceil(growth × probes) points per round,
    /// until every point is a probe or interpolated exactly (the rest then follow by index). The insertion order is the
    /// ranking: a budget is its prefix, the tolerance policy searches its prefixes. Port of the Python reference
    /// (lpnn/quality/placement/insertion.py), irradiance metric; parity pinned by Tests/Data/insertion_golden.json.
    ///
    /// Needs the dense lighting at every evaluation point and a tetrahedraliser (Unity's in the editor). Cost: about
    /// log(N / 4) / log(1 + growth) rounds (~60 for 1,000 points), each one tetrahedralisation of the probes and one
    /// location of the other points (<see cref="InsertionOrder"/> locates only the points whose tetrahedron the last
    /// insertion broke, outside the hull or on a tetrahedron's boundary: <see cref="InsertionRounds"/>).
    ///
    /// Guided insertion (quality.md §5.2): the same rounds, but each cell's candidate is its point of largest error ×
    /// guide weight among those with error above <see cref="Exact"/>, the weights being the network's scores through the
    /// spread ranking's rule (<see cref="GuideWeights"/>). Which cells get a point, their order and the batch size are
    /// unchanged; equal weights give the plain ranking.</summary>
    public static class InsertionRanking
    {
        /// <summary>Points inserted per round, as a fraction of the current probes (chosen on training crops, quality.md §5).</summary>
        public const double DefaultGrowth = 0.1;

        /// <summary>The starting tetrahedron is drawn from this fraction of the points nearest the median lighting.</summary>
        public const double TypicalFraction = 0.1;

        /// <summary>Per-point errors at or below this are exact interpolation: nothing to fix there.</summary>
        public const double Exact = 1e-12;

        /// <summary>Errors (and guided keys, and cell sums) within this of each other count as equal, ties going to the lower
        /// point index (Documentation~/quality.md §5.1): two languages (or two summation orders) compute equal errors a few ulps
        /// apart (~1e-16; sums of 10^5 errors ~1e-11), and errors that differ by less are equally good to fix. Python's
        /// insertion.TIE.</summary>
        public const double Tie = 1e-9;

        /// <summary>Every grid point once, most important first (<see cref="InsertionOrder"/> read to its end).</summary>
        /// <param name="reference">The dense lighting of exactly this grid's points.</param>
        /// <param name="tetrahedralizer">Unity's in the editor; tests use a Delaunay of their own.</param>
        /// <param name="growth">Fraction of the current probes inserted per round (&gt; 0).</param>
        /// <param name="progress">Called before every round with the points ranked so far, and at the end.</param>
        /// <param name="scores">The network's score of every point, or null: guided insertion by <see cref="GuideWeights"/> of
        /// them (quality.md §5.2), else plain insertion.</param>
        public static int[] Rank(EvaluationGrid grid, ReferenceLighting reference, ITetrahedralizer tetrahedralizer, double growth = DefaultGrowth,
            ProgressCallback progress = null, CancellationToken cancel = default, float[] scores = null)
        {
            if (reference == null) throw new ArgumentNullException(nameof(reference));
            return new InsertionOrder(grid, reference, tetrahedralizer, growth, GuideOf(scores, reference.Count)).All(progress, cancel);
        }

        /// <summary>The insertion ranking of the valid points alone (<see cref="InsertionOrder.OfValid"/>), as `lpnn place`
        /// ranks a capture whose points inside geometry were dropped. Returns every grid point once: the valid points in
        /// insertion order, then the invalid ones by index (never selected: <see cref="ProbeSelector.SelectFromRanking"/>
        /// with the same flags drops them).</summary>
        /// <param name="sh">27 floats per grid point (Documentation~/sh.md).</param>
        /// <param name="sceneScale">The whole grid's scene scale, so the errors are those of the full reference.</param>
        /// <param name="valid">One flag per grid point, or null (all valid: <see cref="Rank"/> on the whole grid).</param>
        /// <param name="scores">One score per grid point, or null: guided insertion by the weights of the valid points' scores
        /// (<see cref="InsertionOrder.OfValid"/>), else plain insertion.</param>
        public static int[] RankValid(EvaluationGrid grid, float[] sh, double sceneScale, bool[] valid, ITetrahedralizer tetrahedralizer,
            double growth = DefaultGrowth, ProgressCallback progress = null, CancellationToken cancel = default, float[] scores = null)
        {
            int[] ranked = InsertionOrder.OfValid(grid, sh, sceneScale, valid, tetrahedralizer, growth, scores).All(progress, cancel);
            if (valid == null) return ranked;
            var ranking = new int[grid.Count];
            Array.Copy(ranked, ranking, ranked.Length);
            for (int n = 0, r = ranked.Length; n < grid.Count; n++)
                if (!valid[n]) ranking[r++] = n;
            return ranking;
        }

        /// <summary>One round given the mesh: the points to insert next, in insertion order — per cell its candidate (its
        /// worst interpolated point; guided, its point of largest error × <paramref name="guide"/> weight among those with
        /// error above <see cref="Exact"/>; ties within <see cref="Tie"/> of the largest: lower index), those with error above
        /// <see cref="Exact"/>, by summed cell error (unweighted, largest first; ties within <see cref="Tie"/>: lower index,
        /// <see cref="LargestFirst"/>), the first max(1, ceil(growth × probes)). Empty when every other point is interpolated
        /// exactly.</summary>
        /// <param name="probes">The probes so far (evaluation point indices, in insertion order).</param>
        /// <param name="tetrahedra">4 indices into <paramref name="probes"/> per tetrahedron.</param>
        /// <param name="guide">Null (plain insertion), or one weight per point of <paramref name="reference"/>, each finite and
        /// &gt; 0 (<see cref="GuideWeights"/>): guided insertion (quality.md §5.2).</param>
        /// <param name="allowed">Null, or one flag per point: only flagged points become probes (pinned probes, pins.md: a
        /// point near a pin never does; a cell whose badly interpolated points are all unflagged gets none).</param>
        public static int[] NextBatch(ReferenceLighting reference, int[] probes, int[] tetrahedra, double growth = DefaultGrowth, double[] guide = null,
            bool[] allowed = null)
        {
            if (reference == null) throw new ArgumentNullException(nameof(reference));
            if (tetrahedra == null) throw new ArgumentNullException(nameof(tetrahedra));
            CheckGrowth(growth);
            CheckGuide(guide, reference.Count);
            // (null probes: InterpolateOthers refuses them with its usual message)
            return BatchOf(reference, probes == null ? 0 : probes.Length, tetrahedra.Length / 4, growth, guide, allowed,
                visit => PlacementError.InterpolateOthers(reference, probes, tetrahedra, visit));
        }

        /// <summary><see cref="NextBatch"/>'s choice, given how the round's points are interpolated: <paramref name="interpolate"/>
        /// visits every point that is not a probe once, with its stencil (cells below
        /// <paramref name="cells"/>), in parallel (<see cref="PlacementError.PointVisitor"/>). Shared by NextBatch and the
        /// incremental rounds (<see cref="InsertionRounds"/>).</summary>
        internal static int[] BatchOf(ReferenceLighting reference, int probeCount, int cells, double growth, double[] guide, bool[] allowed,
            Action<PlacementError.PointVisitor> interpolate)
        {
            var cellError = new double[cells];
            int count = reference.Count;
            var errors = new double[count];
            var keys = new double[count];
            var cellOf = new int[count];
            for (int n = 0; n < count; n++) cellOf[n] = -1;
            interpolate((int n, ref Stencil stencil, double[] interpolated) =>
            {
                double e = PointErrorMetrics.Irradiance(interpolated, reference.Light, n * ReferenceLighting.LightValues, reference.SceneScale);
                errors[n] = e;
                cellOf[n] = stencil.Cell;
                // The candidate's key: the error itself, or (guided) error × weight, with points at or below Exact never
                // candidates (key -1), so a cell needs a point exactly when it does unguided.
                double key = guide == null ? e : e > Exact ? e * guide[n] : -1.0;
                if (allowed != null && !allowed[n]) key = double.NegativeInfinity;
                keys[n] = key;
            });
            // The cells' sums after the (parallel) pass, in ascending point order: the same sums on any thread count.
            for (int n = 0; n < count; n++)
                if (cellOf[n] >= 0) cellError[cellOf[n]] += errors[n];
            int[] worst = FirstPerCell(cellOf, keys, cells);  // rows are point indices: the lowest index within Tie of the largest
            var candidates = new List<int>();
            var candidateError = new List<double>();
            for (int c = 0; c < cells; c++)
            {
                if (worst[c] < 0 || !(errors[worst[c]] > Exact) || (allowed != null && !allowed[worst[c]])) continue;
                candidates.Add(worst[c]);
                candidateError.Add(cellError[c]);
            }
            int[] byCellError = LargestFirst(candidateError.ToArray(), candidates.ToArray());
            int take = Math.Min(byCellError.Length, Math.Max(1, (int)Math.Ceiling(growth * probeCount)));
            var batch = new int[take];
            for (int k = 0; k < take; k++) batch[k] = candidates[byCellError[k]];
            return batch;
        }

        /// <summary>Per cell (0 .. <paramref name="cells"/> − 1) the first row whose key is within <see cref="Tie"/> of the
        /// largest key of its cell, or −1 for a cell no row is in; rows of cell −1 are left out. With rows in ascending point
        /// index, a cell's candidate by quality.md §5.1 step 2 and leaks.md's repair (the lowest index among the largest):
        /// errors where the light is even are round-off whose last bits hang on the arithmetic's order, so an exact
        /// comparison would let rounding choose (Python's insertion_kernel.first_per_cell).</summary>
        internal static int[] FirstPerCell(IReadOnlyList<int> cell, IReadOnlyList<double> key, int cells)
        {
            if (cell.Count != key.Count) throw new ArgumentException("cells (" + cell.Count + ") and keys (" + key.Count + ") differ in length");
            var largest = new double[cells];
            for (int c = 0; c < cells; c++) largest[c] = double.NegativeInfinity;
            for (int m = 0; m < cell.Count; m++)
                if (cell[m] >= 0) largest[cell[m]] = Math.Max(largest[cell[m]], key[m]);
            var first = new int[cells];
            for (int c = 0; c < cells; c++) first[c] = -1;
            for (int m = 0; m < cell.Count; m++)
            {
                int c = cell[m];
                if (c >= 0 && first[c] < 0 && key[m] >= largest[c] - Tie) first[c] = m;
            }
            return first;
        }

        /// <summary>Positions of <paramref name="values"/>, largest first, where a value within <see cref="Tie"/> of the next
        /// larger one counts as equal to it: each run of such values goes by <paramref name="index"/>, lowest first
        /// (Documentation~/quality.md §5.1; Python's insertion.largest_first).</summary>
        internal static int[] LargestFirst(double[] values, int[] index)
        {
            int count = values.Length;
            var byValue = new int[count];
            var negated = new double[count];
            for (int k = 0; k < count; k++)
            {
                byValue[k] = k;
                negated[k] = -values[k];
            }
            // A sort on primitive keys (fast at 10^6 values); each run is then a segment of it, put in index order.
            Array.Sort(negated, byValue);
            var indexOf = new int[count];
            for (int k = 0; k < count; k++) indexOf[k] = index[byValue[k]];
            for (int start = 0; start < count;)
            {
                int end = start + 1;
                // Equal values are one run even when infinite (their difference is NaN): refinement's stale costs, −∞.
                while (end < count && (negated[end] == negated[end - 1] || negated[end] - negated[end - 1] <= Tie)) end++;
                if (end - start > 1) Array.Sort(indexOf, byValue, start, end - start);
                start = end;
            }
            return byValue;
        }

        /// <summary>The start (quality.md §5): among the ceil(<see cref="TypicalFraction"/> × N) points (at least 4) whose
        /// lighting is nearest the per-value median (the irradiance error to it; ties: lower index), the one farthest from
        /// their centroid, then farthest-point sampling among them; its first four, completed to a non-flat tetrahedron
        /// from that order and then every other point by index (<see cref="TetrahedronGuarantee"/>). Returned in that
        /// preference order.</summary>
        public static int[] TypicalTetrahedron(EvaluationGrid grid, ReferenceLighting reference)
        {
            if (grid == null) throw new ArgumentNullException(nameof(grid));
            if (reference == null) throw new ArgumentNullException(nameof(reference));
            int n = reference.Count;
            if (grid.Count != n)
                throw new PlacementErrorException("the reference lighting has " + InvariantFormat.Count(n) + " points but the grid has " +
                                                  InvariantFormat.Count(grid.Count) + "; sample the lighting for this grid");
            if (n < ProbeIndices.Minimum)
                throw new PlacementErrorException("the insertion ranking needs at least 4 evaluation points to start from a tetrahedron, got " + n +
                                                  ": make the volume larger or the cell size smaller");
            int[] candidates = NearestMedian(reference, Math.Min(n, Math.Max(4, (int)Math.Ceiling(TypicalFraction * n))));
            // Only the spread order's head is normally needed (its first 4, and the guarantee's first point off their
            // plane): rank a short prefix, and the whole candidate set only when the guarantee reached beyond it.
            for (int length = Math.Min(candidates.Length, SpreadPrefix); ; length = candidates.Length)
            {
                int[] start = StartFrom(grid, SpreadOut(reference.Local, candidates, length), out bool beyondPrefix);
                if (!beyondPrefix || length == candidates.Length) return start;
            }
        }

        /// <summary>The ranking's first points (quality.md §5.1 step 1): <see cref="TypicalTetrahedron"/>, then the grid's
        /// <see cref="ExtremePoints"/> not already listed, first occurrence first. The extremes make the first rounds'
        /// hull span the volume: from four points near its middle most points lie outside the hull, and each round
        /// projects them all onto it (Python's insertion.insertion_start).</summary>
        public static int[] Start(EvaluationGrid grid, ReferenceLighting reference)
        {
            int[] typical = TypicalTetrahedron(grid, reference);
            var listed = new HashSet<int>(typical);
            var start = new List<int>(typical);
            foreach (int p in ExtremePoints(grid))
                if (listed.Add(p)) start.Add(p);
            return start.ToArray();
        }

        /// <summary>Per direction (s_i, s_j, s_k) of signs -1 or +1, in the order (-,-,-), (-,-,+), (-,+,-), …, (+,+,+): the
        /// point of largest s_i·i + s_j·j + s_k·k over its lattice id (exact integers; ties: lower index). 8 entries,
        /// repeats included (a grid has at least one point).</summary>
        public static int[] ExtremePoints(EvaluationGrid grid)
        {
            if (grid == null) throw new ArgumentNullException(nameof(grid));
            var extremes = new int[8];
            var best = new long[8];
            for (int d = 0; d < 8; d++) best[d] = long.MinValue;
            for (int p = 0; p < grid.Count; p++)
            {
                LatticeId id = grid.GetId(p);
                for (int d = 0; d < 8; d++)
                {
                    long value = ((d & 4) != 0 ? id.I : -(long)id.I) + ((d & 2) != 0 ? id.J : -(long)id.J) + ((d & 1) != 0 ? id.K : -(long)id.K);
                    if (value > best[d])
                    {
                        best[d] = value;
                        extremes[d] = p;
                    }
                }
            }
            return extremes;
        }

        /// <summary>Farthest-point steps computed before falling back to the whole candidate set (quality.md §5.1 needs
        /// the spread order only up to the tetrahedron guarantee's pick).</summary>
        private const int SpreadPrefix = 64;

        /// <param name="spread">A prefix of the candidates' spread order (at least 4 points).</param>
        /// <param name="beyondPrefix">Set when the guarantee took a point ranked after that prefix: the answer then
        /// depends on the rest of the spread order, and the caller must pass all of it.</param>
        private static int[] StartFrom(EvaluationGrid grid, int[] spread, out bool beyondPrefix)
        {
            int n = grid.Count;
            var preference = new int[n];
            var rankOf = new int[n];
            var inSpread = new bool[n];
            int next = 0;
            foreach (int p in spread)
            {
                inSpread[p] = true;
                preference[next++] = p;
            }
            for (int p = 0; p < n; p++)
                if (!inSpread[p]) preference[next++] = p;
            for (int r = 0; r < n; r++) rankOf[preference[r]] = r;

            var selected = new HashSet<int>();
            for (int k = 0; k < 4; k++) selected.Add(spread[k]);
            TetrahedronGuarantee.Ensure(grid, preference, selected);
            var start = new int[selected.Count];
            selected.CopyTo(start);
            Array.Sort(start, (a, b) => rankOf[a].CompareTo(rankOf[b]));
            beyondPrefix = rankOf[start[start.Length - 1]] >= spread.Length;
            return start;
        }

        /// <summary>The <paramref name="count"/> points whose 42 values are nearest the per-value median (irradiance error),
        /// nearest first, ties (within <see cref="Tie"/>) to the lower index.</summary>
        private static int[] NearestMedian(ReferenceLighting reference, int count)
        {
            const int values = ReferenceLighting.LightValues;
            int n = reference.Count;
            var median = new double[values];
            var column = new double[n];
            for (int i = 0; i < values; i++)
            {
                for (int p = 0; p < n; p++) column[p] = reference.Light[values * p + i];
                median[i] = Statistics.Median(column);
            }
            // Nearest first: the largest negated deviation (the irradiance error to the median), ties within Tie by index.
            var negatedDeviation = new double[n];
            var points = new int[n];
            for (int p = 0; p < n; p++)
            {
                negatedDeviation[p] = -PointErrorMetrics.Irradiance(median, reference.Light, values * p, reference.SceneScale);
                points[p] = p;
            }
            int[] order = LargestFirst(negatedDeviation, points);
            var nearest = new int[count];
            Array.Copy(order, nearest, count);
            return nearest;
        }

        /// <summary>The first <paramref name="length"/> candidates (point indices) in farthest-point order: first the one
        /// farthest from their centroid (ties: earlier candidate), then unweighted farthest-point sampling (ties: earlier
        /// candidate).</summary>
        private static int[] SpreadOut(double[] local, int[] candidates, int length)
        {
            int count = candidates.Length;
            var x = new double[count];
            var y = new double[count];
            var z = new double[count];
            double cx = 0, cy = 0, cz = 0;
            for (int k = 0; k < count; k++)
            {
                x[k] = local[3 * candidates[k]];
                y[k] = local[3 * candidates[k] + 1];
                z[k] = local[3 * candidates[k] + 2];
                cx += x[k];
                cy += y[k];
                cz += z[k];
            }
            cx /= count;
            cy /= count;
            cz /= count;
            int first = 0;
            double farthest = double.NegativeInfinity;
            for (int k = 0; k < count; k++)
            {
                double dx = x[k] - cx, dy = y[k] - cy, dz = z[k] - cz;
                double d = Math.Sqrt(dx * dx + dy * dy + dz * dz);
                if (d > farthest)
                {
                    farthest = d;
                    first = k;
                }
            }
            var ones = new double[count];
            for (int k = 0; k < count; k++) ones[k] = 1;
            int[] order = FarthestPointSampling.Rank(x, y, z, ones, new[] { first }, length);
            var spread = new int[length];
            for (int k = 0; k < length; k++) spread[k] = candidates[order[k]];
            return spread;
        }

        /// <summary>Guided insertion's per-point weights from the network's scores (quality.md §5.2): the spread ranking's
        /// weights (selection.md: clip to [1e-6, 1], NaN → 1e-6, sqrt(score / median)), all finite and &gt; 0. Python's
        /// insertion.guide_weights.</summary>
        public static double[] GuideWeights(float[] scores) => SpreadWeights.Compute(scores);

        /// <summary>Guided insertion uses the network's scores only on volumes of at most this many points (quality.md §5.2:
        /// chosen on whole training and validation levels; on larger clouds than the network ever saw its guide did worse
        /// than none). Python's insertion.GUIDED_POINT_LIMIT.</summary>
        public const int GuidedPointLimit = 32768;

        /// <summary>Null for null scores or more than <see cref="GuidedPointLimit"/> points (plain insertion), else
        /// <see cref="GuideWeights"/> of one score per point (an error otherwise). Python's insertion.guide_of.</summary>
        internal static double[] GuideOf(float[] scores, int pointCount)
        {
            CheckScoreCount(scores, pointCount);
            return scores == null || pointCount > GuidedPointLimit ? null : GuideWeights(scores);
        }

        /// <summary>Null, or one score per point (an error saying so otherwise).</summary>
        internal static void CheckScoreCount(float[] scores, int pointCount)
        {
            if (scores != null && scores.Length != pointCount)
                throw new PlacementErrorException("guided insertion needs one score per evaluation point: got " + InvariantFormat.Count(scores.Length) +
                                                  " scores for " + InvariantFormat.Count(pointCount) + " points; score this grid again");
        }

        /// <summary>Null, or one weight per point, each finite and &gt; 0; else an error naming the first bad weight (Python's
        /// insertion.checked_guide).</summary>
        internal static void CheckGuide(double[] guide, int pointCount)
        {
            if (guide == null) return;
            if (guide.Length != pointCount)
                throw new PlacementErrorException("guide weights must be one number per point (" + InvariantFormat.Count(pointCount) + "), got " +
                                                  InvariantFormat.Count(guide.Length) + ": build them with InsertionRanking.GuideWeights(scores) of these points' scores");
            int first = -1, bad = 0;
            for (int n = 0; n < guide.Length; n++)
            {
                if (guide[n] > 0 && !double.IsInfinity(guide[n])) continue;  // false for NaN
                if (first < 0) first = n;
                bad++;
            }
            if (first >= 0)
                throw new PlacementErrorException("guide weight " + first + " = " + InvariantFormat.Number(guide[first]) + " must be a finite number greater than 0 (" +
                                                  InvariantFormat.Count(bad) + " such weights): build them with InsertionRanking.GuideWeights(scores)");
        }

        internal static void CheckGrowth(double growth)
        {
            if (!(growth > 0) || double.IsInfinity(growth))
                throw new PlacementErrorException("growth " + InvariantFormat.Number(growth) + " must be a fraction greater than 0 of the current probes (e.g. " +
                                                  InvariantFormat.Number(DefaultGrowth) + ")");
        }
    }
}
