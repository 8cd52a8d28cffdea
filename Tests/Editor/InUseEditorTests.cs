using System.IO;
using System.Linq;
using System.Threading;
using Lpnn.Probes.Core;
using Lpnn.Probes.Core.Captures;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Scoring;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.InUse;
using Lpnn.Probes.Core.Selection;
using Lpnn.Probes.Core.Sh;
using NUnit.Framework;
using UnityEditor;
using UnityEditor.SceneManagement;
using UnityEngine;
using NumericsVector3 = System.Numerics.Vector3;

namespace Lpnn.Probes.Editor.Tests
{
    /// <summary>The in-use rule at the Grid step (Documentation~/in-use.md) on a scene of primitive colliders: a floor whose top
    /// is at y = −0.25 and a block whose top, at y = 2.2, is 2.45 m above it (far more than a step). The volume's points lie
    /// at multiples of 0.5 m, x −3.5…3.5, y 0.5…5.5, z −1.5…1.5 (1,155 points); every decision is at least 0.2 m from its
    /// threshold. Above the open floor the points up to y = 2.5 are within the 3 m band (2.75 m) and those from y = 3.0 are
    /// not (3.25 m); above the block (x 2…3, z −0.5…0.5) the points from y = 2.5 to 5.0 are in band but no character climbs
    /// there from a seed on the floor. Edit Mode tests: they need the Unity editor (never run in this repository, which only
    /// compiles them).</summary>
    [TestFixture]
    public class InUseEditorTests
    {
        private const float FloorTop = -0.25f, BlockTop = 2.2f;
        private const int AllPoints = 15 * 11 * 7;

        private LpnnVolume _volume;
        private LpnnSession _session;
        private Transform _seed;
        private string _folder;

        [SetUp]
        public void BuildScene()
        {
            EditorSceneManager.NewScene(NewSceneSetup.EmptyScene, NewSceneMode.Single);
            Box("Floor", new Vector3(0, FloorTop - 0.1f, 0), new Vector3(12, 0.2f, 12));
            Box("Block", new Vector3(2.5f, (FloorTop + BlockTop) / 2, 0), new Vector3(1.4f, BlockTop - FloorTop, 1.4f));  // x 1.8…3.2, z −0.7…0.7
            _seed = new GameObject("Spawn point").transform;
            _seed.position = new Vector3(-3, 0, 0);
            _volume = LpnnMenuItems.CreateVolume(null);
            _volume.transform.position = Vector3.zero;
            _volume.SetBoxes(new LpnnBox(new Vector3(0, 3, 0), new Vector3(7.5f, 5.5f, 3.5f), Vector3.zero));
            _volume.SetCellSize(0.5f);
            _session = LpnnSession.For(_volume);
            _folder = Path.Combine(Path.GetTempPath(), "lpnn-in-use-tests-" + System.Guid.NewGuid().ToString("N"));
        }

        [TearDown]
        public void Cleanup()
        {
            LpnnSession.Forget(_volume);
            if (Directory.Exists(_folder)) Directory.Delete(_folder, true);
        }

        private static void Box(string name, Vector3 center, Vector3 size)
        {
            var box = GameObject.CreatePrimitive(PrimitiveType.Cube);  // with its BoxCollider
            box.name = name;
            box.transform.position = center;
            box.transform.localScale = size;
        }

        private static bool AboveBlock(NumericsVector3 p) => p.X > 1.8f && p.X < 3.2f && p.Z > -0.7f && p.Z < 0.7f;
        /// <summary>Above the open floor, within the band (2.75 m at most above it).</summary>
        private static bool LowOverFloor(NumericsVector3 p) => !AboveBlock(p) && p.Y < 2.9f;
        /// <summary>Above the block's top, within the band (y 2.5…5.0; 5.5 is 3.3 m above it).</summary>
        private static bool OnTheBlock(NumericsVector3 p) => AboveBlock(p) && p.Y > BlockTop && p.Y < BlockTop + 3;

        [Test]
        public void ANewVolumeUsesTheDefaultRuleWithTheSpecsParameters()
        {
            Assert.That(_volume.InUseRule, Is.EqualTo(InUseRules.Default));
            Assert.That(_volume.InUseBandHeight, Is.EqualTo(3f));
            Assert.That(_volume.InUseSlopeLimit, Is.EqualTo(45f));
            Assert.That(_volume.InUseStepHeight, Is.EqualTo(0.5f));
            Assert.That(_volume.InUseSeeds, Is.Empty);
            Assert.That(_volume.UseNavMesh, Is.True);
        }

        [Test]
        public void BandKeepsThePointsWithinTheBandAboveEveryWalkableFloor()
        {
            _volume.SetInUseRule(InUseRule.Band);
            var result = LpnnPipeline.BuildGrid(_volume, _session, null, CancellationToken.None);
            var grid = _session.Grid;
            Assert.That(result.Grid, Is.SameAs(grid));
            Assert.That(_session.InUse.PointsBefore, Is.EqualTo(AllPoints));
            Assert.That(grid.Count, Is.EqualTo(_session.InUse.InUseCount));
            Assert.That(grid.Count, Is.LessThan(AllPoints));
            var all = _session.InUse.AllPoints;
            for (int n = 0; n < all.Count; n++)
            {
                var p = all.GetPosition(n);
                if (LowOverFloor(p) || OnTheBlock(p)) Assert.That(_session.InUse.InUseOfAll[n], Is.True, "point " + p + " lies in the band");
                else if (!AboveBlock(p)) Assert.That(_session.InUse.InUseOfAll[n], Is.False, "point " + p + " is 3.25 m or more above the floor");
            }
            for (int n = 0; n < grid.Count; n++) Assert.That(all.IndexOf(grid.GetId(n)), Is.GreaterThanOrEqualTo(0));
            StringAssert.Contains("points in use (band", StepSummaries.Describe(result));
            StringAssert.Contains("physics rays", _session.InUse.FloorSource, "no NavMesh is baked in this scene");
        }

        [Test]
        public void ReachableWalksFromTheSeedOverTheFloorButNotOntoTheBlock()
        {
            _volume.SetInUseSeeds(_seed);
            Assert.That(_volume.InUseRule, Is.EqualTo(InUseRule.Reachable), "the default rule");
            LpnnPipeline.BuildGrid(_volume, _session);
            var inUse = _session.InUse;
            var all = inUse.AllPoints;
            int onBlock = 0;
            for (int n = 0; n < all.Count; n++)
            {
                var p = all.GetPosition(n);
                if (LowOverFloor(p)) Assert.That(inUse.InUseOfAll[n], Is.True, "point " + p + " is walked to from the seed");
                if (!OnTheBlock(p)) continue;
                onBlock++;
                Assert.That(inUse.InUseOfAll[n], Is.False, "point " + p + " is on top of a 2.45 m block");
            }
            Assert.That(onBlock, Is.EqualTo(3 * 3 * 6));
            Assert.That(_session.Grid.Count, Is.EqualTo(inUse.InUseCount));
            Assert.That(inUse.SeedCount, Is.EqualTo(1));
        }

        [Test]
        public void AllKeepsEveryPointAndTheReachableMaskForTheReports()
        {
            _volume.SetInUseRule(InUseRule.All);
            _volume.SetInUseSeeds(_seed);
            LpnnPipeline.BuildGrid(_volume, _session);
            Assert.That(_session.Grid.Count, Is.EqualTo(AllPoints));
            var inUse = _session.InUse;
            Assert.That(inUse.MaskRule, Is.EqualTo(InUseRule.Reachable));
            Assert.That(inUse.GridMask, Is.SameAs(inUse.InUseOfAll));
            for (int n = 0; n < _session.Grid.Count; n++)
            {
                var p = _session.Grid.GetPosition(n);
                if (LowOverFloor(p)) Assert.That(inUse.GridMask[n], Is.True, "point " + p);
                if (OnTheBlock(p) || p.Y > 3.1f) Assert.That(inUse.GridMask[n], Is.False, "point " + p);
            }

            _volume.SetInUseSeeds();
            LpnnPipeline.BuildGrid(_volume, _session);
            Assert.That(_session.InUse.MaskRule, Is.EqualTo(InUseRule.Band), "without seeds, All reports at the band points");
            Assert.That(_session.Grid.Count, Is.EqualTo(AllPoints));
        }

        [Test]
        public void LightingAndPlacementWorkOnThePointsInUseAndReportTheirError()
        {
            _volume.SetInUseRule(InUseRule.Band);
            _volume.SetMethod(PlacementMethod.Insertion);
            _volume.SetSelection(SelectionSettings.Budget(24, true));
            bool completed = LpnnPipeline.Run(_volume, _session, PipelineStep.Placement, volume => new GradientLighting(), (step, work) =>
            {
                work(null, CancellationToken.None);
                return true;
            });
            Assert.That(completed, Is.True);
            var grid = _session.Grid;
            Assert.That(_session.Sh.Length, Is.EqualTo(ShMath.FloatsPerProbe * grid.Count), "lighting sampled at the points in use only");
            Assert.That(_session.Features.PointCount, Is.EqualTo(grid.Count));
            var placed = LpnnPipeline.Apply(_volume, _session, null, CancellationToken.None);
            Assert.That(placed.Positions.Length, Is.GreaterThanOrEqualTo(4));
            foreach (var position in placed.Positions)
                Assert.That(position.Y < 2.9f || AboveBlock(position), Is.True, "probe at " + position + " lies outside the band");
            Assert.That(placed.ErrorAtPointsInUse, Is.Not.Null);
            Assert.That(placed.ErrorAtPointsInUse.Points, Is.EqualTo(grid.Count));
            var direct = PlacementInputs.Evaluator(_session, grid).Evaluate(placed.Selection.Indices).Irradiance.Mean;
            Assert.That(placed.ErrorAtPointsInUse.Summary.Mean, Is.EqualTo(direct), "Band's grid holds only the points in use");
            StringAssert.Contains("error at the " + grid.Count.ToString("N0", System.Globalization.CultureInfo.InvariantCulture) + " points in use",
                StepSummaries.Describe(placed));
        }

        /// <summary>The volume under All with the seed, 24 probes by budget (no refinement), run through Features under the
        /// gradient lighting and applied: what the report-mask tests read.</summary>
        private PlacementResult AppliedUnderAll()
        {
            _volume.SetInUseRule(InUseRule.All);
            _volume.SetInUseSeeds(_seed);
            _volume.SetSelection(SelectionSettings.Budget(24, true));
            _volume.SetMethod(PlacementMethod.Insertion);  // no refinement
            LpnnPipeline.Run(_volume, _session, PipelineStep.Features, volume => new GradientLighting(), (step, work) =>
            {
                work(null, CancellationToken.None);
                return true;
            });
            return LpnnPipeline.Apply(_volume, _session, null, CancellationToken.None);
        }

        [Test]
        public void LeaksAreCountedOverTheMaskWithUnitysTetrahedraAndPhysicsRays()
        {
            // Documentation~/leaks.md "What is reported": the inspector's leak line after Apply under All counts the report
            // mask's points only, as LeakCheck.Find decides them with the same tetrahedra and the scene's colliders.
            var placed = AppliedUnderAll();
            var grid = LpnnPipeline.PlacementGrid(_volume, _session);
            var probes = placed.Selection.Indices;
            var entry = LeaksAtPointsInUse.Run(_volume, _session, grid, probes);
            Assert.That(entry, Is.Not.Null);
            Assert.That(entry.Failed, Is.False, entry.Text);
            Assert.That(LeaksAtPointsInUse.Known(_volume, _session, probes), Is.SameAs(entry));
            var mask = _session.InUse.GridMask;
            Assert.That(entry.Report.Points, Is.EqualTo(mask.Count(m => m)));
            var reference = PlacementInputs.Reference(_session, grid);
            var positions = probes.Select(p => reference.GetPosition(p)).ToArray();
            int[] tetrahedra = new UnityTetrahedralizer().Tetrahedralize(positions);
            bool[] leaking;
            using (new RaycastScope(_volume, _volume.AddTemporaryColliders))
                leaking = Core.Quality.LeakCheck.Find(reference, probes, tetrahedra, new PhysicsRaycaster(_volume.gameObject.scene));
            Assert.That(entry.Report.Leaking, Is.EqualTo(Core.Quality.LeakReport.CountTrue(leaking, mask)));
            Assert.That(entry.Corners.Length, Is.EqualTo(4 * System.Math.Min(entry.Report.TetrahedronCount, LeaksAtPointsInUse.MaxDrawnTetrahedra)));
            StringAssert.StartsWith("Leaks: " + entry.Report.Leaking.ToString("N0", System.Globalization.CultureInfo.InvariantCulture) + " of ", entry.Text);
            LeaksAtPointsInUse.Forget(_volume);
            Assert.That(LeaksAtPointsInUse.Last(_volume), Is.Null);
        }

        [Test]
        public void AllMeasuresTheErrorAtTheMaskAndExportsTheInUseSection()
        {
            var placed = AppliedUnderAll();
            var errors = PlacementInputs.Evaluator(_session, _session.Grid).Evaluate(placed.Selection.Indices).PointIrradiance;
            var mask = _session.InUse.GridMask;
            double sum = 0;
            int count = 0;
            for (int n = 0; n < errors.Length; n++)
                if (mask[n]) { sum += errors[n]; count++; }
            Assert.That(placed.ErrorAtPointsInUse.Points, Is.EqualTo(count));
            Assert.That(placed.ErrorAtPointsInUse.Summary.Mean, Is.EqualTo(sum / count).Within(1e-12));

            string path = CaptureExport.Save(_volume, _session, Path.Combine(_folder, "all"), out string _);
            var capture = CaptureFile.Read(path);
            Assert.That(capture.PointCount, Is.EqualTo(AllPoints));
            Assert.That(capture.Source.Get("in_use").AsString, Is.EqualTo("all"));
            Assert.That(capture.Source.Get("in_use_report_rule").AsString, Is.EqualTo("reachable"));
            Assert.That(capture.Source.Get("in_use_band_height").AsNumber, Is.EqualTo(3.0));
            Assert.That(capture.Source.Get("in_use_slope_limit").AsNumber, Is.EqualTo(45.0));
            Assert.That(capture.Source.Get("in_use_step_height").AsNumber, Is.EqualTo(0.5));
            Assert.That(capture.Source.Get("in_use_seeds").AsNumber, Is.EqualTo(1));
            Assert.That(capture.Source.Get("points_before_in_use").AsNumber, Is.EqualTo(AllPoints));
            var section = capture.ExtraSections.Single(s => s.Name == "in_use");
            Assert.That(section.DType, Is.EqualTo("uint8"));
            Assert.That(section.Data, Is.EqualTo(mask.Select(flag => flag ? (byte)1 : (byte)0).ToArray()));
        }

        [Test]
        public void ABandCaptureHoldsThePointsInUseAndNoInUseSection()
        {
            _volume.SetInUseRule(InUseRule.Band);
            LpnnPipeline.Run(_volume, _session, PipelineStep.Features, volume => new GradientLighting(), (step, work) =>
            {
                work(null, CancellationToken.None);
                return true;
            });
            var capture = CaptureFile.Read(CaptureExport.Save(_volume, _session, Path.Combine(_folder, "band"), out string _));
            Assert.That(capture.PointCount, Is.EqualTo(_session.Grid.Count));
            Assert.That(capture.Source.Get("in_use").AsString, Is.EqualTo("band"));
            Assert.That(capture.Source.Get("points_before_in_use").AsNumber, Is.EqualTo(AllPoints));
            Assert.That(capture.ExtraSections.Any(s => s.Name == "in_use"), Is.False);
            Assert.That(capture.Source.Has("in_use_report_rule"), Is.False, "only All carries a report rule");
        }

        [Test]
        public void ReachableWithoutSeedsKeepsTheBandAndABandThatHoldsNothingIsRefusedWithTheFix()
        {
            // A new volume (Reachable, no seeds) keeps the band's points and says why in the grid summary.
            LpnnPipeline.BuildGrid(_volume, _session);
            Assert.That(_session.InUse.Rule, Is.EqualTo(InUseRule.Band));
            StringAssert.Contains("no In Use Seeds", _session.InUse.FloorSource);

            _volume.SetInUseRule(InUseRule.Band);
            _volume.SetInUseParameters(0.125f, 45, 0.5f);
            var nothing = Assert.Throws<LpnnException>(() => LpnnPipeline.BuildGrid(_volume, _session));
            StringAssert.Contains("no point in use", nothing.Message);
            StringAssert.Contains("band height 0.125 m", nothing.Message);

            _volume.SetInUseParameters(3, 90, 0.5f);
            StringAssert.Contains("slope_limit_degrees 90", Assert.Throws<LpnnException>(() => LpnnPipeline.BuildGrid(_volume, _session)).Message);

            _volume.SetInUseRule(InUseRule.Reachable);
            _volume.SetInUseParameters(3, 45, 0.5f);
            _volume.SetInUseSeeds(_seed, null);
            StringAssert.Contains("entry 1 of the In Use Seeds", Assert.Throws<LpnnException>(() => LpnnPipeline.BuildGrid(_volume, _session)).Message);
        }

        [Test]
        public void ChangingAnInUseSettingAsksToRebuildTheGrid()
        {
            _volume.SetInUseRule(InUseRule.Band);
            LpnnPipeline.BuildGrid(_volume, _session);
            Assert.That(LpnnPipeline.FreshGrid(_volume, _session), Is.SameAs(_session.Grid));
            _volume.SetInUseParameters(2.5f, 45, 0.5f);
            StringAssert.Contains("in-use settings changed", Assert.Throws<LpnnException>(() => LpnnPipeline.FreshGrid(_volume, _session)).Message);
            _volume.SetInUseParameters(3, 45, 0.5f);
            Assert.That(LpnnPipeline.FreshGrid(_volume, _session), Is.SameAs(_session.Grid));
            _volume.SetInUseRule(InUseRule.Reachable);
            _volume.SetInUseSeeds(_seed);
            Assert.Throws<LpnnException>(() => LpnnPipeline.FreshGrid(_volume, _session));
            LpnnPipeline.BuildGrid(_volume, _session);
            _seed.position += new Vector3(0.5f, 0, 0);
            Assert.Throws<LpnnException>(() => LpnnPipeline.FreshGrid(_volume, _session), "a moved seed changes the walk");
        }

        /// <summary>Scores outlive the session through the project's Library (LpnnScores, issue 31): with the scene saved the
        /// volume has a stable GlobalObjectId, the Scoring result is written under Library/LpnnProbes/Scores, and a new session
        /// (as after a script reload) reads it back and finds the scored in-use points again without casting the rule's rays.</summary>
        [Test]
        public void StoredScoresOfTheInUsePointsFindTheirGridAgainAfterTheSessionIsLost()
        {
            const string scenePath = "Assets/LpnnScoresTest.unity";
            Assert.That(EditorSceneManager.SaveScene(_volume.gameObject.scene, scenePath), Is.True);
            try
            {
                _volume.SetInUseRule(InUseRule.Band);
                LpnnPipeline.BuildGrid(_volume, _session);
                var grid = _session.Grid;
                var record = new ScoreRecord();
                record.Set(grid.CopyIds(), new float[grid.Count], grid.CellSize, "test", "test", null);
                record.SetGridSignature(_session.GridSignature);
                LpnnScores.Store(_volume, record);
                Assert.That(_session.ScoresUnwritten, Is.False, "a saved scene: the record went to the Library");

                LpnnSession.Forget(_volume);  // as a script reload drops it
                _session = LpnnSession.For(_volume);
                Assert.That(LpnnScores.For(_volume), Is.Not.SameAs(record), "read back from the Library, not kept in memory");
                Assert.That(LpnnScores.For(_volume).Ids, Is.EqualTo(record.Ids));
                var rebuilt = LpnnPipeline.ScoredGrid(_volume, _session);
                Assert.That(rebuilt.CopyIds(), Is.EqualTo(grid.CopyIds()));
                Assert.That(_session.InUse.PointsBefore, Is.EqualTo(AllPoints));

                LpnnSession.Forget(_volume);
                _session = LpnnSession.For(_volume);
                _volume.SetInUseParameters(2.5f, 45, 0.5f);
                StringAssert.Contains("the volume changed since scoring", Assert.Throws<LpnnException>(() => LpnnPipeline.ScoredGrid(_volume, _session)).Message);
            }
            finally
            {
                LpnnScores.DeleteStoredCopy(_volume);
                AssetDatabase.DeleteAsset(scenePath);
            }
        }

        /// <summary>Lighting that changes along x and y, so insertion has something to place; no bake.</summary>
        private sealed class GradientLighting : IEvaluationLighting, ILightSampler
        {
            public string Description => "gradient test lighting";

            public float[] Sample(EvaluationGrid grid, ProgressCallback progress, CancellationToken cancel) =>
                FeatureExtractor.SampleLighting(grid, this, progress, cancel);

            public void Sample(NumericsVector3[] positions, float[] sh)
            {
                for (int p = 0; p < positions.Length; p++)
                {
                    int o = p * ShMath.FloatsPerProbe;
                    for (int c = 0; c < ShMath.FloatsPerProbe; c++) sh[o + c] = 0;
                    float x = positions[p].X, y = positions[p].Y;
                    ShMath.AddAmbient(sh, o, new NumericsVector3(0.2f + 0.05f * x * x, 0.3f + 0.1f * y, 0.25f));
                }
            }

            public void Dispose() { }
        }
    }
}
