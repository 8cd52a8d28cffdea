using System.Runtime.CompilerServices;
using System.Threading;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Quality;
using Lpnn.Probes.Core.Selection;
using Lpnn.Probes.Core.Scoring;

namespace Lpnn.Probes.Editor
{
    /// <summary>What placement reuses between inspector repaints, held as long as the arrays it was made from: the
    /// rankings of a set of scores (the spread ranking is O(N log N)) and the reference lighting of a set of SH (42
    /// values per point). Keyed by array identity — a new Lighting or Scoring result is a new array, so nothing stale
    /// is ever returned — and weakly, so they go when the session drops the arrays.</summary>
    public static class PlacementInputs
    {
        private static readonly ConditionalWeakTable<float[], ScoredPoints> Rankings = new ConditionalWeakTable<float[], ScoredPoints>();
        private static readonly ConditionalWeakTable<float[], ReferenceLighting> References = new ConditionalWeakTable<float[], ReferenceLighting>();
        private static readonly ConditionalWeakTable<float[], InsertionOrderSlots> InsertionOrders = new ConditionalWeakTable<float[], InsertionOrderSlots>();

        /// <summary>An insertion order (computed as far as it was read) with the grid it ranks, the features whose validity
        /// flags it used (null: none) and the scores that guided it (null: plain insertion); the whole ranking once it was
        /// read to its end.</summary>
        private sealed class InsertionOrderEntry
        {
            public EvaluationGrid Grid;
            public FeatureSet Features;
            public float[] GuideScores;
            /// <summary>The pins the order starts from (null: none); see <see cref="KeptPins"/>.</summary>
            public Pins Pins;
            public Core.Quality.InsertionOrder Order;
            public int[] Ranking;

            /// <summary>Made from exactly these inputs (arrays and objects by identity: a new Features or Scoring result, or
            /// other pins, is a new object, so a stale order never matches).</summary>
            public bool Matches(EvaluationGrid grid, FeatureSet features, float[] guideScores, Pins pins) =>
                Grid == grid && Features == features && ReferenceEquals(GuideScores, guideScores) && Pins == pins;
        }

        /// <summary>The orders of one lighting: plain insertion and guided insertion are kept side by side, so switching the
        /// method back and forth recomputes neither; an order that starts from pinned probes is kept beside them, so turning
        /// Keep Pinned Probes off and on recomputes none either.</summary>
        private sealed class InsertionOrderSlots
        {
            public InsertionOrderEntry Plain;
            public InsertionOrderEntry Guided;
            public InsertionOrderEntry Pinned;
        }

        /// <summary>A volume's pins snapped to a grid's valid points, and what they were snapped from.</summary>
        private sealed class PinsEntry
        {
            public FeatureSet Features;
            public Double3[] Positions;
            /// <summary>The snapped pins, or null with <see cref="Refusal"/> set (a bad pin is refused at every repaint without
            /// measuring again).</summary>
            public Pins Pins;
            public string Refusal;
        }

        /// <summary>The last pins snapped per grid: snapping costs pins × points distances, too much for every repaint, and the
        /// pinned insertion order is keyed by the Pins object, so the same pins must give the same object.</summary>
        private static readonly ConditionalWeakTable<EvaluationGrid, PinsEntry> SnappedPins = new ConditionalWeakTable<EvaluationGrid, PinsEntry>();

        /// <summary>The grid's stored scores and valid points with their rankings (computed on first use, then kept; the
        /// record replaces its validity flags together with its scores, so the scores' identity is the key).</summary>
        internal static ScoredPoints Scored(EvaluationGrid grid, ScoreRecord record)
        {
            var scores = record.Scores;
            if (Rankings.TryGetValue(scores, out var points) && points.Grid == grid) return points;
            Rankings.Remove(scores);
            points = new ScoredPoints(grid, scores, record.Valid);
            Rankings.Add(scores, points);
            return points;
        }

        /// <summary>Computes (and keeps) the spread ranking of the stored scores now, e.g. under a step's progress bar, so that
        /// the inspector's first repaint does not pay for it.</summary>
        internal static void ComputeSpreadOrder(EvaluationGrid grid, ScoreRecord record) => _ = Scored(grid, record).SpreadOrder;

        /// <summary>The lighting the placement error compares against: the Lighting step's SH at the session's grid.</summary>
        public static ReferenceLighting Reference(LpnnSession session, EvaluationGrid grid)
        {
            if (session.Sh == null || session.Grid != grid)
                throw new LpnnException("the placement error compares against the lighting at every evaluation point, and there is none for this " +
                                        "grid (a script reload or a grid change drops it): run the Lighting data step");
            return References.GetValue(session.Sh, sh => ReferenceLighting.FromGrid(grid, sh));
        }

        /// <summary>The insertion ranking of the session's lighting (quality.md §5) with Unity's tetrahedralisation: computed on
        /// first use (about a second per 1,000 points, with progress and cancel), then kept as long as that lighting.</summary>
        /// <param name="guideScores">One score per grid point (the Scoring step's, already checked to be this grid's:
        /// LpnnPipeline.PlacementGrid): guided insertion (quality.md §5.2); null: plain insertion.</param>
        public static int[] RankByInsertion(LpnnSession session, EvaluationGrid grid, ProgressCallback progress, CancellationToken cancel,
            float[] guideScores = null) =>
            RankByInsertion(session, grid, progress, cancel, guideScores, null);

        /// <summary>As the public overload, starting from <paramref name="pins"/> when given (<see cref="KeptPins"/>): the
        /// pinned order of Documentation~/pins.md, which ranks the pins first and no point within the keep distance of one.</summary>
        internal static int[] RankByInsertion(LpnnSession session, EvaluationGrid grid, ProgressCallback progress, CancellationToken cancel,
            float[] guideScores, Pins pins)
        {
            var entry = InsertionEntry(session, grid, guideScores, pins);
            if (entry.Ranking == null) entry.Ranking = entry.Order.All(progress, cancel);
            return entry.Ranking;
        }

        /// <summary>The insertion order of the session's lighting (guided by <paramref name="guideScores"/> when given), computed
        /// only as far as a selection reads it (a budget, the tolerance search): `Apply` and batch mode place without ranking
        /// every point. Kept as long as that lighting (and those scores), so what was computed is reused (also by
        /// <see cref="RankByInsertion"/>).</summary>
        public static Core.Quality.InsertionOrder InsertionOrder(LpnnSession session, EvaluationGrid grid, float[] guideScores = null) =>
            InsertionEntry(session, grid, guideScores, null).Order;

        /// <summary>As the public overload, starting from <paramref name="pins"/> when given (<see cref="KeptPins"/>).</summary>
        internal static Core.Quality.InsertionOrder InsertionOrder(LpnnSession session, EvaluationGrid grid, float[] guideScores, Pins pins) =>
            InsertionEntry(session, grid, guideScores, pins).Order;

        private static InsertionOrderEntry InsertionEntry(LpnnSession session, EvaluationGrid grid, float[] guideScores, Pins pins)
        {
            var features = ValidPoints(session, grid) == null ? null : session.Features;
            var known = KnownEntry(session, grid, features, guideScores, pins);
            if (known != null) return known;
            var reference = Reference(session, grid);
            // Only the valid points are ranked (points inside geometry would steer the rounds with lighting read in walls), and
            // only their scores make the guide's weights (as `lpnn place --guided`: the median is the valid points').
            var order = Core.Quality.InsertionOrder.OfValid(grid, session.Sh, reference.SceneScale, ValidPoints(session, grid), new UnityTetrahedralizer(),
                pins, InsertionRanking.DefaultGrowth, guideScores);
            var entry = new InsertionOrderEntry { Grid = grid, Features = features, GuideScores = guideScores, Pins = pins, Order = order };
            var slots = InsertionOrders.GetValue(session.Sh, sh => new InsertionOrderSlots());
            if (pins != null) slots.Pinned = entry;
            else if (guideScores == null) slots.Plain = entry;
            else slots.Guided = entry;
            return entry;
        }

        /// <summary>The kept order of these inputs, or null.</summary>
        private static InsertionOrderEntry KnownEntry(LpnnSession session, EvaluationGrid grid, FeatureSet features, float[] guideScores, Pins pins)
        {
            if (session.Sh == null || !InsertionOrders.TryGetValue(session.Sh, out var slots)) return null;
            var entry = pins != null ? slots.Pinned : guideScores == null ? slots.Plain : slots.Guided;
            return entry != null && entry.Matches(grid, features, guideScores, pins) ? entry : null;
        }

        /// <summary>The kept insertion order of these inputs, however far it was computed, or null (never computes).</summary>
        public static Core.Quality.InsertionOrder KnownInsertionOrder(LpnnSession session, EvaluationGrid grid, float[] guideScores = null) =>
            KnownInsertionOrder(session, grid, guideScores, null);

        /// <summary>As the public overload, for the order that starts from <paramref name="pins"/> when given.</summary>
        internal static Core.Quality.InsertionOrder KnownInsertionOrder(LpnnSession session, EvaluationGrid grid, float[] guideScores, Pins pins)
        {
            if (session.Sh == null || session.Grid != grid) return null;
            var features = ValidPoints(session, grid) == null ? null : session.Features;
            return KnownEntry(session, grid, features, guideScores, pins)?.Order;
        }

        /// <summary>The whole insertion ranking (guided by <paramref name="guideScores"/> when given) if it was already computed
        /// for this lighting, grid, validity and scores, else null (never computes: the inspector's repaint must stay fast).</summary>
        public static int[] KnownInsertionRanking(LpnnSession session, EvaluationGrid grid, float[] guideScores = null) =>
            KnownInsertionRanking(session, grid, guideScores, null);

        /// <summary>As the public overload, for the order that starts from <paramref name="pins"/> when given: known once ranked
        /// to its end (Rank by insertion), since a pinned order never ranks its blocked points and so is never "complete".</summary>
        internal static int[] KnownInsertionRanking(LpnnSession session, EvaluationGrid grid, float[] guideScores, Pins pins)
        {
            if (session.Sh == null || session.Grid != grid) return null;
            var features = ValidPoints(session, grid) == null ? null : session.Features;
            var known = KnownEntry(session, grid, features, guideScores, pins);
            if (known == null) return null;
            if (known.Ranking == null && known.Order.IsComplete) known.Ranking = known.Order.All();
            return known.Ranking;
        }

        /// <summary>The pins Apply keeps for this volume on <paramref name="grid"/> (Core's <see cref="Pins.KeptBy"/>: null when
        /// Keep Pinned Probes is off, an error for the Network method), snapped to the grid's valid points once per grid,
        /// validity and positions, so the preview's repaints and Apply get the same object.</summary>
        internal static Pins KeptPins(LpnnSession session, EvaluationGrid grid, PlacementMethod method, bool keep, UnityEngine.Vector3[] world)
        {
            var positions = new Double3[world.Length];
            for (int p = 0; p < world.Length; p++) positions[p] = new Double3(world[p].x, world[p].y, world[p].z);
            // Off, or the Network method's refusal: nothing to snap or keep.
            if (!keep || !PlacementMethods.RanksByInsertion(method)) return Pins.KeptBy(method, keep, positions, grid, null);
            var features = ValidPoints(session, grid) == null ? null : session.Features;
            if (!SnappedPins.TryGetValue(grid, out var kept) || kept.Features != features || !SamePositions(kept.Positions, positions))
            {
                kept = new PinsEntry { Features = features, Positions = positions };
                try
                {
                    kept.Pins = Pins.KeptBy(method, true, positions, grid, ValidPoints(session, grid));
                }
                catch (PinException e)
                {
                    kept.Refusal = e.Message;
                }
                SnappedPins.Remove(grid);
                SnappedPins.Add(grid, kept);
            }
            if (kept.Pins == null) throw new PinException(kept.Refusal);
            return kept.Pins;
        }

        private static bool SamePositions(Double3[] a, Double3[] b)
        {
            if (a.Length != b.Length) return false;
            for (int p = 0; p < a.Length; p++)
                if (!a[p].Equals(b[p])) return false;
            return true;
        }

        /// <summary>The Features step's validity flags for this grid (features.md "Probe validity"), or null when the Features
        /// step has not run on it (then every point is a candidate: the inspector says so).</summary>
        public static bool[] ValidPoints(LpnnSession session, EvaluationGrid grid)
        {
            if (session.Features == null || session.Grid != grid) return null;
            return Core.Pipeline.ApplySteps.ValidPoints(session.Features);
        }

        /// <summary>Measures probe sets of this grid with Unity's tetrahedralisation.</summary>
        public static PlacementEvaluator Evaluator(LpnnSession session, EvaluationGrid grid) =>
            new PlacementEvaluator(Reference(session, grid), new UnityTetrahedralizer());
    }
}
