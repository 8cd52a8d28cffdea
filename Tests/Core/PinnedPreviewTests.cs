using System.Collections.Generic;
using System.Linq;
using System.Numerics;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Pipeline;
using Lpnn.Probes.Core.Quality;
using Lpnn.Probes.Core.Selection;
using Lpnn.Probes.Core.Tests.Support;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    /// <summary>The inspector's preview of the insertion methods (<see cref="ApplySteps.PreviewByInsertion"/>) counts pinned
    /// probes as Apply does (Documentation~/pins.md): the pins are kept, count in the budget, and no new probe comes within the
    /// keep distance of one; and <see cref="Pins.KeptBy"/> decides, for Apply, the preview and batch mode alike, which
    /// volumes keep pins.</summary>
    [TestFixture]
    public class PinnedPreviewTests
    {
        private EvaluationGrid _grid;
        private float[] _sh;
        private double _scale;
        /// <summary>The layer x = 0 is inside geometry: the orders rank the other points only.</summary>
        private bool[] _valid;
        private Pins _pins;

        [SetUp]
        public void MakeScene()
        {
            _grid = QualityFixtures.Box(7, 5, 4);
            _sh = QualityFixtures.BlobField(QualityFixtures.Positions(_grid), new Vector3(2, 1, 1), new Vector3(5, 3, 2), 1.3f);
            _scale = ReferenceLighting.FromGrid(_grid, _sh).SceneScale;
            _valid = Enumerable.Range(0, _grid.Count).Select(n => _grid.GetId(n).I > 0).ToArray();
            _pins = Pins.Snap(_grid, ArtistPositions(), null, _valid);
        }

        /// <summary>Seven probes a quarter cell off valid grid points, spread over the box (none at x = 0).</summary>
        private Double3[] ArtistPositions()
        {
            var pins = new List<Double3>();
            for (int n = 0; n < _grid.Count && pins.Count < 8; n += 17)
            {
                if (!_valid[n]) continue;
                var v = _grid.GetPosition(n);
                pins.Add(new Double3(v.X + 0.25, v.Y, v.Z - 0.25));
            }
            return pins.ToArray();
        }

        private InsertionOrder PinnedOrder() => InsertionOrder.OfValid(_grid, _sh, _scale, _valid, new BowyerWatsonDelaunay(), _pins);

        private InsertionOrder PinFreeOrder() => InsertionOrder.OfValid(_grid, _sh, _scale, _valid, new BowyerWatsonDelaunay());

        [TestCase(SelectionPolicy.Budget, 30)]
        [TestCase(SelectionPolicy.Spread, 12)]
        [TestCase(SelectionPolicy.Percentile, 0.8)]
        public void ThePreviewIsApplysSelectionWithEveryPinCountedInTheBudget(SelectionPolicy policy, double value)
        {
            var settings = new SelectionSettings { Policy = policy, Value = value };
            int[] ranking = PinnedOrder().All();
            var preview = ApplySteps.PreviewByInsertion(_grid, _valid, ranking, settings, _pins);

            Assert.That(_pins.Count, Is.EqualTo(7));
            Assert.That(_pins.Indices.Except(preview.Indices), Is.Empty, "every pin is in the preview");
            Assert.That(preview.Indices.Where(p => _pins.Blocked[p] && !_pins.Indices.Contains(p)), Is.Empty,
                "no new probe within the keep distance of a pin");
            Assert.That(preview.Indices.All(p => _valid[p]), Is.True);
            // The pins count in the policy's probes: a budget of K places K, not K plus the pins.
            int candidates = _valid.Count(v => v);
            int expected = policy == SelectionPolicy.Percentile ? ProbeSelector.PercentileCount(value, candidates) : (int)value;
            Assert.That(preview.Indices.Length, Is.EqualTo(expected));
            // Apply's own selection (a fresh pinned order read lazily, no refinement) is the preview, point for point.
            var applied = ApplySteps.SelectByInsertion(_grid, _valid, null, PinnedOrder(), settings, null, false, null, null, default, _pins);
            Assert.That(preview.Indices, Is.EqualTo(applied.Indices));
        }

        [TestCase(true)]
        [TestCase(false)]
        public void APreviewFromThePinFreeRankingIsRefusedWhenPinsAreKept(bool someInsideGeometry)
        {
            // The inspector's old preview selected from the pin-free ranking and so showed a count without the pins (with
            // every point valid it even succeeded: a selection that lacked them).
            bool[] valid = someInsideGeometry ? _valid : null;
            var pins = Pins.Snap(_grid, ArtistPositions(), null, valid);
            int[] pinFree = InsertionOrder.OfValid(_grid, _sh, _scale, valid, new BowyerWatsonDelaunay()).All();
            var error = Assert.Throws<PinException>(() => ApplySteps.PreviewByInsertion(_grid, valid, pinFree, SelectionSettings.Budget(30), pins));
            StringAssert.Contains("the insertion ranking was made without these 7 pinned probes", error.Message);
            StringAssert.Contains("Rank by insertion", error.Message);
            Assert.That(pins.Heads(pinFree), Is.False);
            Assert.That(pins.Heads(InsertionOrder.OfValid(_grid, _sh, _scale, valid, new BowyerWatsonDelaunay(), pins).All()), Is.True);
        }

        [Test]
        public void ABudgetBelowThePinsIsRefusedByThePreviewAsByApply()
        {
            int[] ranking = PinnedOrder().All();
            var error = Assert.Throws<PinException>(() => ApplySteps.PreviewByInsertion(_grid, _valid, ranking, SelectionSettings.Budget(5), _pins));
            StringAssert.Contains("the budget keeps 5 probes but 7 are pinned: raise the budget to at least 7 probes", error.Message);
        }

        [Test]
        public void ThePreviewTakesTheOrdersRankingOfTheValidPointsAlone()
        {
            // The editor keeps InsertionOrder.All(): the valid points only, shorter than the grid. Selecting from it with
            // ProbeSelector.SelectFromRanking (the old preview) failed with "need a ranking of all 140 points".
            int[] validOnly = PinFreeOrder().All();
            Assert.That(validOnly.Length, Is.LessThan(_grid.Count));
            var settings = SelectionSettings.Budget(20, true);
            var preview = ApplySteps.PreviewByInsertion(_grid, _valid, validOnly, settings, null);
            int[] everyPoint = InsertionRanking.RankValid(_grid, _sh, _scale, _valid, new BowyerWatsonDelaunay());
            Assert.That(preview.Indices, Is.EqualTo(ProbeSelector.SelectFromRanking(_grid, everyPoint, settings, null, _valid).Indices));
            Assert.That(ApplySteps.PreviewByInsertion(_grid, _valid, everyPoint, settings, null).Indices, Is.EqualTo(preview.Indices),
                "a ranking of every grid point gives the same preview");
        }

        [Test]
        public void TheTolerancePolicyIsNotPreviewedWithoutItsSearch()
        {
            var error = Assert.Throws<SelectionException>(() =>
                ApplySteps.PreviewByInsertion(_grid, _valid, PinnedOrder().All(), SelectionSettings.Tolerance(0.05), _pins));
            StringAssert.Contains("Find probes", error.Message);
        }

        [Test]
        public void OnlyTheInsertionMethodsKeepPinsAndOnlyWhenAsked()
        {
            var positions = ArtistPositions();
            Assert.That(Pins.KeptBy(PlacementMethod.Insertion, false, positions, _grid, _valid), Is.Null, "the toggle is off: stored pins are ignored");
            Assert.That(Pins.KeptBy(PlacementMethod.Network, false, positions, _grid, _valid), Is.Null);
            var network = Assert.Throws<PinException>(() => Pins.KeptBy(PlacementMethod.Network, true, positions, _grid, _valid));
            Assert.That(network.Message, Is.EqualTo(Pins.NeedsInsertionMethod));
            foreach (var method in new[] { PlacementMethod.InsertionRefined, PlacementMethod.Insertion, PlacementMethod.GuidedInsertionRefined, PlacementMethod.GuidedInsertion })
                Assert.That(Pins.KeptBy(method, true, positions, _grid, _valid).Indices, Is.EqualTo(_pins.Indices), method.ToString());
            var none = Assert.Throws<PinException>(() => Pins.KeptBy(PlacementMethod.Insertion, true, new Double3[0], _grid, _valid));
            StringAssert.Contains("no pinned positions were given", none.Message);
        }
    }
}
