using System;
using System.Collections.Generic;
using System.Diagnostics;
using System.Linq;
using System.Numerics;
using System.Threading;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Pipeline;
using Lpnn.Probes.Core.Quality;
using Lpnn.Probes.Core.Selection;
using Lpnn.Probes.Core.Tests.Support;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    /// <summary>Cancel at every progress call of the whole Apply (issue 31, Deliver 4; Documentation~/ci.md "Apply rehearsal"):
    /// <see cref="ApplySteps.Rehearse"/> — lighting, features (rays and solid colliders), valid points, insertion, the
    /// tolerance search and the batched refinement, in the editor's step order — on a small synthetic scene, so that every
    /// one of its progress calls can be the one the user cancels at (the real-level rehearsal, ApplyRehearsalTests, tries 4 of
    /// ~170). After each cancel: the group holds what it held (never written), the state the steps publish into (the editor
    /// session's stand-in, <see cref="ApplyState"/>) holds only whole results of the steps that finished, and an Apply run
    /// afterwards from that state — reusing the insertion order the cancelled run left, as the inspector's Apply does —
    /// places exactly what an uncancelled run places.</summary>
    [TestFixture]
    public class ApplyCancelTests
    {
        private const double Tau = 0.03;
        private static readonly Vector3[] Before = { new Vector3(9, 9, 9), new Vector3(8, 8, 8) };

        /// <summary>A LightProbeGroup stand-in: its positions change only when written.</summary>
        private sealed class Group : IProbeGroupWriter
        {
            public Vector3[] Positions = (Vector3[])Before.Clone();
            public int Writes;

            public void Write(Vector3[] positions)
            {
                Writes++;
                Positions = positions;
            }
        }

        /// <summary>Two coloured blobs (QualityFixtures.BlobField) at whatever points are asked.</summary>
        private sealed class BlobLighting : ILightSampler
        {
            public void Sample(Vector3[] positions, float[] sh)
            {
                var field = QualityFixtures.BlobField(positions, new Vector3(1, 1, 1), new Vector3(4, 3, 2), 1.3f);
                Array.Copy(field, sh, field.Length);
            }
        }

        /// <summary>Open space: every ray misses (no back faces), so only the pillar's collider makes points invalid.</summary>
        private sealed class OpenSpace : IRaycaster
        {
            public void Cast(Vector3[] origins, Vector3[] directions, float maxDistance, RayHit[] results)
            {
                for (int r = 0; r < origins.Length; r++) results[r] = RayHit.Miss;
            }
        }

        /// <summary>The test Delaunay, remembered: a tetrahedralisation is a function of the positions, and the ~160 runs of the
        /// cancel test ask for the same ones again (this keeps the test at seconds; the answers are BowyerWatsonDelaunay's).</summary>
        private sealed class RememberedDelaunay : ITetrahedralizer
        {
            private readonly BowyerWatsonDelaunay _delaunay = new BowyerWatsonDelaunay();
            private readonly Dictionary<ulong, List<KeyValuePair<Vector3[], int[]>>> _known = new Dictionary<ulong, List<KeyValuePair<Vector3[], int[]>>>();
            public int Computed;

            public int[] Tetrahedralize(Vector3[] positions)
            {
                ulong hash = 14695981039346656037UL;  // FNV-1a over the coordinates' bits
                foreach (var p in positions)
                {
                    hash = (hash ^ (uint)BitConverter.ToInt32(BitConverter.GetBytes(p.X), 0)) * 1099511628211UL;
                    hash = (hash ^ (uint)BitConverter.ToInt32(BitConverter.GetBytes(p.Y), 0)) * 1099511628211UL;
                    hash = (hash ^ (uint)BitConverter.ToInt32(BitConverter.GetBytes(p.Z), 0)) * 1099511628211UL;
                }
                if (!_known.TryGetValue(hash, out var entries)) _known[hash] = entries = new List<KeyValuePair<Vector3[], int[]>>();
                foreach (var entry in entries)
                    if (entry.Key.SequenceEqual(positions)) return (int[])entry.Value.Clone();
                int[] tetrahedra = _delaunay.Tetrahedralize(positions);
                entries.Add(new KeyValuePair<Vector3[], int[]>((Vector3[])positions.Clone(), tetrahedra));
                Computed++;
                return (int[])tetrahedra.Clone();
            }
        }

        private sealed class Scene
        {
            public EvaluationGrid Grid;
            public FeatureStep Features;
            public readonly BlobLighting Lighting = new BlobLighting();
            public readonly RememberedDelaunay Tetrahedralizer = new RememberedDelaunay();
            public readonly SelectionSettings Settings = SelectionSettings.Tolerance(Tau);
        }

        private static Scene NewScene()
        {
            // 5 × 4 × 3 points at 1 m; a BoxCollider pillar through x = 2, z = 1 (4 points inside, never probes).
            var pillar = new InsideCollidersTests.FakeColliders().Box(new Vector3(1.5f, -1, 0.5f), new Vector3(2.5f, 6, 1.5f));
            return new Scene { Grid = QualityFixtures.Box(5, 4, 3), Features = ApplySteps.Features(new OpenSpace(), pillar) };
        }

        private static SelectionResult Run(Scene scene, ApplyState state, Group group, ProgressCallback progress, CancellationToken cancel,
            ITetrahedralizer tetrahedralizer = null) =>
            ApplySteps.Rehearse(scene.Grid, scene.Lighting, scene.Features, tetrahedralizer ?? scene.Tetrahedralizer, scene.Settings, true, group, progress,
                cancel, state);

        /// <summary>Counts the tetrahedralisations asked for once the token is cancelled (there must be none: each is work the
        /// user no longer wants).</summary>
        private sealed class AfterCancel : ITetrahedralizer
        {
            private readonly ITetrahedralizer _inner;
            private readonly CancellationToken _cancel;
            public int Calls;

            public AfterCancel(ITetrahedralizer inner, CancellationToken cancel)
            {
                _inner = inner;
                _cancel = cancel;
            }

            public int[] Tetrahedralize(Vector3[] positions)
            {
                if (_cancel.IsCancellationRequested) Calls++;
                return _inner.Tetrahedralize(positions);
            }
        }

        private sealed class Baseline
        {
            public Scene Scene;
            public ApplyState State;
            public Group Group;
            public SelectionResult Selection;
            public List<string> Stages = new List<string>();
            public int[] Ranking;
        }

        private static Baseline Uncancelled()
        {
            var b = new Baseline { Scene = NewScene(), State = new ApplyState(), Group = new Group() };
            b.Selection = Run(b.Scene, b.State, b.Group, (stage, done, total) => b.Stages.Add(stage), CancellationToken.None);
            // The whole insertion ranking of these inputs, to check what a cancelled run left against.
            b.Ranking = InsertionOrder.OfValid(b.State.Grid, b.State.Sh, b.State.Reference.SceneScale, ApplySteps.ValidPoints(b.State.Features),
                b.Scene.Tetrahedralizer).All();
            return b;
        }

        [Test]
        public void TheSyntheticApplyRunsEveryStepAndWritesOnce()
        {
            var b = Uncancelled();
            Assert.That(b.Group.Writes, Is.EqualTo(1));
            Assert.That(b.Group.Positions, Is.EqualTo(ApplySteps.PositionsOf(b.Scene.Grid, b.Selection)));
            var valid = ApplySteps.ValidPoints(b.State.Features);
            Assert.That(ValidCandidates.CountInvalid(valid), Is.EqualTo(4), "the pillar's points");
            Assert.That(b.State.Features.InsideColliderCount, Is.EqualTo(4));
            Assert.That(b.Selection.Indices.All(p => valid[p]), Is.True, "no probe inside the pillar");
            var evaluator = new PlacementEvaluator(b.State.Reference, b.Scene.Tetrahedralizer);
            Assert.That(evaluator.MeanError(b.Selection.Indices), Is.LessThanOrEqualTo(Tau));
            Assert.That(b.Selection.Indices.Length, Is.LessThan(valid.Count(v => v)), "the tolerance search stopped short of every point");
            var stages = new HashSet<string>(b.Stages);
            foreach (string stage in new[] { ApplySteps.LightingStage, "casting rays", InsideColliders.Stage, "insertion ranking", ReportingMeasure.Stage, "batched refinement" })
                Assert.That(stages, Has.Member(stage), "the Apply reports progress in every step");
        }

        [Test]
        public void ACancelAtEveryProgressCallLeavesTheGroupUnchangedAndNoPartialState()
        {
            var clock = Stopwatch.StartNew();
            var b = Uncancelled();
            int n = b.Stages.Count;
            Assert.That(n, Is.GreaterThan(20));
            var cancelledIn = new HashSet<string>();
            for (int k = 1; k <= n; k++)
            {
                string at = "cancel at progress call " + k + " of " + n + " (" + b.Stages[k - 1] + ")";
                var state = new ApplyState();
                var group = new Group();
                using (var source = new CancellationTokenSource())
                {
                    int calls = 0;
                    ProgressCallback progress = (stage, done, total) =>
                    {
                        if (++calls == k) source.Cancel();
                    };
                    var watch = new AfterCancel(b.Scene.Tetrahedralizer, source.Token);
                    Assert.Throws(Is.InstanceOf<OperationCanceledException>(), () => Run(b.Scene, state, group, progress, source.Token, watch), at);
                    // Honoured at once: every progress call is followed by a cancel check (the editor reads its Cancel button
                    // inside the call), so nothing more is reported or tetrahedralised.
                    Assert.That(calls, Is.EqualTo(k), at + ": progress reported after the cancel (" +
                                                      string.Join(" | ", b.Stages.Skip(k).Take(Math.Max(0, calls - k))) + ")");
                    Assert.That(watch.Calls, Is.EqualTo(0), at + ": tetrahedralisations after the cancel");
                }
                cancelledIn.Add(b.Stages[k - 1]);

                // The group: never written, still what it held.
                Assert.That(group.Writes, Is.EqualTo(0), at);
                Assert.That(group.Positions, Is.EqualTo(Before), at);

                // The state: each published result whole (those of an uncancelled run), nothing of the step cancelled.
                if (state.Sh != null) Assert.That(state.Sh, Is.EqualTo(b.State.Sh), at + ": lighting");
                if (state.Features != null)
                {
                    Assert.That(state.Sh, Is.Not.Null, at);
                    Assert.That(state.Features.Values, Is.EqualTo(b.State.Features.Values), at + ": features");
                    Assert.That(state.Features.BackFaceFractions, Is.EqualTo(b.State.Features.BackFaceFractions), at + ": validity");
                }
                if (state.KeptOrder != null)
                {
                    int[] ranked = state.KeptOrder.Prefix(0);  // what the cancelled run ranked, computing nothing more
                    Assert.That(ranked, Is.EqualTo(b.Ranking.Take(ranked.Length).ToArray()), at + ": the kept insertion order is a prefix of the whole ranking");
                }

                // Apply again from what was left (the inspector's Apply when lighting and features are there, else Run all).
                var again = new Group();
                var selection = state.Features != null
                    ? ApplySteps.Place(state, b.Scene.Tetrahedralizer, b.Scene.Settings, true, again, null, CancellationToken.None)
                    : Run(b.Scene, state, again, null, CancellationToken.None);
                Assert.That(selection.Indices, Is.EqualTo(b.Selection.Indices), at + ": the next Apply places what an uncancelled one does");
                Assert.That(again.Writes, Is.EqualTo(1), at);
                Assert.That(again.Positions, Is.EqualTo(b.Group.Positions), at);
            }
            Assert.That(cancelledIn, Is.EquivalentTo(new HashSet<string>(b.Stages)), "a cancel was tried in every stage");
            Console.WriteLine("synthetic Apply: cancel tried at all " + n + " progress calls (" + string.Join(", ", new HashSet<string>(b.Stages)) +
                              ") in " + clock.Elapsed.TotalSeconds.ToString("F1", System.Globalization.CultureInfo.InvariantCulture) + " s");
        }
    }
}
