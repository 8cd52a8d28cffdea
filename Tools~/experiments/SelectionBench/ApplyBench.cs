using System;
using System.Collections.Generic;
using System.Diagnostics;
using System.Globalization;
using System.Numerics;
using System.Threading;
using Lpnn.Probes.Core.Captures;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Pipeline;
using Lpnn.Probes.Core.Placement;
using Lpnn.Probes.Core.Quality;
using Lpnn.Probes.Core.Selection;
using Lpnn.Probes.Core.Tests.Support;

/// <summary>The whole Apply of the volume's default (Insertion, refined in batches, τ = 0.05) on a real level's capture,
/// leak-aware (Avoid light leaks, the volume's default) when given the level's triangles — cast through
/// <see cref="TriangleSoupRaycaster"/>, standing in for Unity's physics — and leak-blind otherwise, timed per stage (issue 30, Deliver 1; Documentation~/benchmarks.md "The C# core under Mono"): the Apply rehearsal's run
/// (Tests/Core/Support/RehearsalApply.cs: ApplySteps.Rehearse with the capture's SH and features) with Python's
/// tetrahedraliser over a pipe (<see cref="PythonTetrahedralizer"/>), wrapped to count the tetrahedralisations and the
/// seconds spent waiting on them per stage. A stage is known from the C# frames that asked for the tetrahedralisation
/// (InsertionOrder: an insertion round; ReportingMeasure: a tolerance-search evaluation; BatchedRefinementState.Evaluate,
/// RemovalCosts, Without: the refinement's seed, trial, commit — only those whose star refills were refused or checked;
/// StarRefills: a hull vertex's link, a few points, counted apart; RefinedSelection: the final check) and from the progress
/// calls; wall time is charged to the stage running since the last switch. The leak-aware Apply's leak repair of the seed
/// (LeakRepair) is a stage of its own; the rays each stage casts, and the seconds inside the raycaster, are counted by a
/// wrapper of the raycaster. Prints figures, and whether the probes are those of <c>lpnn place</c>'s probes file when
/// given one; asserts nothing.</summary>
public static class ApplyBench
{
    public const double Tolerance = 0.05;

    private const string Before = "before the first tetrahedralisation (features fake, reference lighting x2, typical tetrahedron)";
    private const string Insertion = "insertion rounds";
    private const string Search = "tolerance search evaluations";
    private const string Repair = "leak repair of the seed";
    private const string Refinement = "batched refinement";
    private const string Other = "other";
    private const string Link = "link";
    private static readonly string[] Stages = { Before, Insertion, Search, Repair, Refinement, Other };

    private sealed class StagedTetrahedralizer : ITetrahedralizer
    {
        private readonly ITetrahedralizer _inner;
        private readonly Stopwatch _clock = Stopwatch.StartNew();
        private double _since;
        public string Current = "lighting (fake)";
        public readonly Dictionary<string, double> Wall = new Dictionary<string, double>();
        public readonly Dictionary<string, double> Waiting = new Dictionary<string, double>();
        /// <summary>Calls per stage, and per kind inside the refinement ("refinement: seed" etc.).</summary>
        public readonly Dictionary<string, int> Calls = new Dictionary<string, int>();
        public int Total;

        public StagedTetrahedralizer(ITetrahedralizer inner) { _inner = inner; }

        public double Elapsed => _clock.Elapsed.TotalSeconds;

        public void Switch(string stage)
        {
            double now = Elapsed;
            Add(Wall, Current, now - _since);
            _since = now;
            Current = stage;
        }

        /// <summary>Tetrahedralisations of one star's link (StarRefills: a hull vertex's refill, a few points each),
        /// counted apart from the probe sets' (<see cref="Total"/>); their waiting is the refinement's.</summary>
        public int LinkCalls;
        public double LinkWaiting;

        public int[] Tetrahedralize(Vector3[] positions)
        {
            string kind = Classify(new StackTrace(1, false));
            if (kind == Link)
            {
                LinkCalls++;
                double asked = Elapsed;
                int[] linkTetrahedra = _inner.Tetrahedralize(positions);
                LinkWaiting += Elapsed - asked;
                Add(Waiting, Refinement, Elapsed - asked);
                return linkTetrahedra;
            }
            string stage = kind.StartsWith("refinement", StringComparison.Ordinal) ? Refinement : kind;
            Switch(stage);
            Calls[kind] = Count(Calls, kind) + 1;
            if (kind != stage) Calls[stage] = Count(Calls, stage) + 1;
            Total++;
            double start = Elapsed;
            int[] tetrahedra = _inner.Tetrahedralize(positions);
            Add(Waiting, stage, Elapsed - start);
            if (Total % 25 == 0)
                Console.Error.WriteLine(string.Format(CultureInfo.InvariantCulture, "[{0:F0} s] {1} tetrahedralisations: insertion {2}, search {3}, refinement {4} ({5} probes in the last)",
                    Elapsed, Total, Count(Calls, Insertion), Count(Calls, Search), Count(Calls, Refinement), positions.Length));
            return tetrahedra;
        }

        /// <summary>The innermost frame of a known Core step decides.</summary>
        private static string Classify(StackTrace trace)
        {
            foreach (var frame in trace.GetFrames() ?? new StackFrame[0])
            {
                var method = frame.GetMethod();
                string type = method?.DeclaringType?.FullName ?? "";
                if (type.StartsWith("Lpnn.Probes.Core.Quality.InsertionOrder", StringComparison.Ordinal)) return Insertion;
                if (type.StartsWith("Lpnn.Probes.Core.Quality.LeakRepair", StringComparison.Ordinal)) return Repair;
                if (type.StartsWith("Lpnn.Probes.Core.Selection.ReportingMeasure", StringComparison.Ordinal) ||
                    type.StartsWith("Lpnn.Probes.Core.Selection.ToleranceSearch", StringComparison.Ordinal)) return Search;
                if (type.StartsWith("Lpnn.Probes.Core.Quality.StarRefills", StringComparison.Ordinal)) return Link;
                if (type.StartsWith("Lpnn.Probes.Core.Quality.BatchedRefinementState", StringComparison.Ordinal))
                {
                    if (method.Name == "Evaluate") return "refinement: seed";
                    if (method.Name == "RemovalCosts") return "refinement: trial";
                    if (method.Name == "Without") return "refinement: commit";
                }
                if (type == "Lpnn.Probes.Core.Quality.BatchedRefinement") return "refinement: other";
                if (type.StartsWith("Lpnn.Probes.Core.Quality.RefinedSelection", StringComparison.Ordinal)) return "refinement: final check";
            }
            return Other;
        }

        private static void Add(Dictionary<string, double> sums, string key, double value) => sums[key] = (sums.TryGetValue(key, out double v) ? v : 0) + value;
        public static int Count(Dictionary<string, int> counts, string key) => counts.TryGetValue(key, out int c) ? c : 0;
        public static double Sum(Dictionary<string, double> sums, string key) => sums.TryGetValue(key, out double v) ? v : 0;
        public static void Add(Dictionary<string, long> sums, string key, long value) => sums[key] = (sums.TryGetValue(key, out long v) ? v : 0) + value;
        public static long Sum(Dictionary<string, long> sums, string key) => sums.TryGetValue(key, out long v) ? v : 0;
    }

    /// <summary>Rays and seconds inside the raycaster, charged to the stage the tetrahedraliser wrapper is in. Each ray to its
    /// own end, as the raycaster it wraps (both of the benchmark's can), so the segments are cast as Unity's physics casts them.</summary>
    private sealed class StagedRaycaster : IPerRayDistanceRaycaster
    {
        private readonly IPerRayDistanceRaycaster _inner;
        private readonly StagedTetrahedralizer _stages;
        public readonly Dictionary<string, long> Rays = new Dictionary<string, long>();
        public readonly Dictionary<string, double> Seconds = new Dictionary<string, double>();

        public StagedRaycaster(IPerRayDistanceRaycaster inner, StagedTetrahedralizer stages)
        {
            _inner = inner;
            _stages = stages;
        }

        public void Cast(Vector3[] origins, Vector3[] directions, float maxDistance, RayHit[] results) =>
            Timed(origins.LongLength, () => _inner.Cast(origins, directions, maxDistance, results));

        public void Cast(Vector3[] origins, Vector3[] directions, float[] maxDistances, RayHit[] results) =>
            Timed(origins.LongLength, () => _inner.Cast(origins, directions, maxDistances, results));

        private void Timed(long rays, Action cast)
        {
            var clock = Stopwatch.StartNew();
            cast();
            StagedTetrahedralizer.Add(Rays, _stages.Current, rays);
            Seconds[_stages.Current] = StagedTetrahedralizer.Sum(Seconds, _stages.Current) + clock.Elapsed.TotalSeconds;
        }
    }

    /// <param name="geometry">The level's triangles (write_capture_triangles.py), for the leak-aware Apply through
    /// <see cref="TriangleSoupRaycaster"/>; null: see <paramref name="embreeScript"/>.</param>
    /// <param name="embreeScript">A shell script running embree_raycaster_server.py on the capture, for the leak-aware Apply
    /// through Python's Embree (<see cref="PipeRaycaster"/>); null with no geometry either: leak-blind.</param>
    /// <param name="rememberSegments">False: the leak-aware refinement casts every segment anew (LeakWeighting without its memo).</param>
    /// <param name="expected">lpnn place's probes file on the same capture, compared with the probes written; null: none.</param>
    /// <param name="refills">False: the refinement tetrahedralises every trial and commit instead of refilling the
    /// candidates' stars (BatchedRefinementState.ForceTetrahedralisation; the code before them, for a comparison under the same load).</param>
    /// <param name="meshes">How the insertion rounds get their tetrahedra (InsertionTetrahedra.Mode): derived by insertion
    /// (the default) or tetrahedralised every round (--tetrahedralised-rounds); both numbered by TetrahedronNumbering, they
    /// must keep the same probes.</param>
    internal static int Run(string capturePath, string script, double tolerance, string geometry, string embreeScript, bool rememberSegments, string expected,
        bool refills = true, InsertionTetrahedra.Mode meshes = InsertionTetrahedra.Mode.Derived)
    {
        BatchedRefinementState.ForceTetrahedralisation = !refills;
        InsertionTetrahedra.Setting = meshes;
        var fallbacks = new SortedDictionary<string, int>(StringComparer.Ordinal);
        InsertionTetrahedra.FallbackListener = reason => fallbacks[reason] = (fallbacks.TryGetValue(reason, out int n) ? n : 0) + 1;
        var read = Stopwatch.StartNew();
        var capture = CaptureFile.Read(capturePath);
        var grid = capture.ToGrid();
        double readSeconds = read.Elapsed.TotalSeconds;
        Console.WriteLine(string.Format(CultureInfo.InvariantCulture, "{0}: {1:N0} points, tau {2} (capture read in {3:F1} s)",
            System.IO.Path.GetFileName(capturePath), capture.PointCount, tolerance, readSeconds));
        IPerRayDistanceRaycaster soup = null;
        string memo = rememberSegments ? "remembered (SegmentMemo)" : "cast anew (no memo)";
        if (geometry != null)
        {
            read.Restart();
            var triangles = TriangleSoupRaycaster.Read(geometry);
            soup = triangles;
            Console.WriteLine(string.Format(CultureInfo.InvariantCulture, "leak-aware (Avoid light leaks), segments {0}, rays through the C# hierarchy over the level's {1:N0} triangles (built in {2:F1} s)",
                memo, triangles.TriangleCount, read.Elapsed.TotalSeconds));
        }
        else if (embreeScript != null)
        {
            soup = new PipeRaycaster(embreeScript);
            Console.WriteLine("leak-aware (Avoid light leaks), segments " + memo + ", rays through Python's Embree over a pipe (lpnn place's own answers)");
        }
        else Console.WriteLine("leak-blind (Avoid light leaks off)");
        if (!refills) Console.WriteLine("no star refills: every trial and commit of the refinement tetrahedralised (--no-refills)");
        if (Lpnn.Probes.Core.Numerics.ParallelChunks.ForcedChunks == 1) Console.WriteLine("every per-point pass on the calling thread (--serial)");
        if (meshes == InsertionTetrahedra.Mode.Tetrahedralised) Console.WriteLine("insertion rounds tetrahedralised every round (--tetrahedralised-rounds)");
        // The first stage's two parts, timed alone (the Apply computes the reference twice: its evaluator's and its order's).
        read.Restart();
        var reference = ReferenceLighting.FromGrid(grid, capture.Sh);
        double referenceSeconds = read.Elapsed.TotalSeconds;
        read.Restart();
        InsertionRanking.TypicalTetrahedron(grid, reference);
        Console.WriteLine(string.Format(CultureInfo.InvariantCulture, "timed alone: reference lighting {0:F1} s, typical tetrahedron {1:F1} s",
            referenceSeconds, read.Elapsed.TotalSeconds));
        reference = null;
        using (var python = new PythonTetrahedralizer(script))
        {
            var staged = new StagedTetrahedralizer(python);
            var rays = soup == null ? null : new StagedRaycaster(soup, staged);
            var writes = new List<Vector3[]>();
            int refinementProgress = 0, insertionRounds = 0;
            ProgressCallback progress = (stage, done, total) =>
            {
                if (stage == ApplySteps.LightingStage && done == total) staged.Switch(Before);
                else if (stage == ReportingMeasure.Stage) staged.Switch(Search);
                else if (stage == "insertion ranking")
                {
                    staged.Switch(Insertion);
                    if (done < total) insertionRounds++;  // InsertionOrder.Prefix reports before every round, and once when done
                }
                else if (stage == "batched refinement") refinementProgress++;
            };
            var selection = RehearsalApply.Run(capture, grid, staged, SelectionSettings.Tolerance(tolerance), true, writes, progress, CancellationToken.None,
                rays, rememberSegments);
            staged.Switch("done");
            double wallTotal = 0, waitTotal = 0;
            Console.WriteLine("stage | wall s | waiting on the tetrahedraliser s | C# own s | tetrahedralisations | rays cast | in the raycaster s");
            long raysTotal = 0;
            double castTotal = 0;
            foreach (string stage in Stages)
            {
                double wall = StagedTetrahedralizer.Sum(staged.Wall, stage), wait = StagedTetrahedralizer.Sum(staged.Waiting, stage);
                int calls = StagedTetrahedralizer.Count(staged.Calls, stage);
                long cast = rays == null ? 0 : StagedTetrahedralizer.Sum(rays.Rays, stage);
                double casting = rays == null ? 0 : StagedTetrahedralizer.Sum(rays.Seconds, stage);
                if ((stage == Other || stage == Repair) && wall == 0 && calls == 0) continue;
                wallTotal += wall;
                waitTotal += wait;
                raysTotal += cast;
                castTotal += casting;
                Console.WriteLine(string.Format(CultureInfo.InvariantCulture, "{0} | {1:F1} | {2:F1} | {3:F1} | {4} | {5:N0} | {6:F1}",
                    stage, wall, wait, wall - wait, calls, cast, casting));
            }
            Console.WriteLine(string.Format(CultureInfo.InvariantCulture, "total (lighting fake: {0:F1} s) | {1:F1} | {2:F1} | {3:F1} | {4} | {5:N0} | {6:F1}",
                StagedTetrahedralizer.Sum(staged.Wall, "lighting (fake)"), wallTotal, waitTotal, wallTotal - waitTotal, staged.Total, raysTotal, castTotal));
            var refinementKinds = new List<string>();
            foreach (var pair in staged.Calls)
                if (pair.Key.StartsWith("refinement: ", StringComparison.Ordinal)) refinementKinds.Add(pair.Key.Substring(12) + " " + pair.Value);
            refinementKinds.Sort(StringComparer.Ordinal);
            Console.WriteLine(string.Format(CultureInfo.InvariantCulture,
                "star refills' link tetrahedralisations (a hull vertex's few points each, not counted above): {0:N0}, {1:F1} s waiting (in the refinement's)",
                staged.LinkCalls, staged.LinkWaiting));
            Console.WriteLine(string.Format(CultureInfo.InvariantCulture, "insertion rounds: {0}, tetrahedralisations for them: {1}",
                insertionRounds, StagedTetrahedralizer.Count(staged.Calls, Insertion)));
            foreach (var pair in fallbacks) Console.WriteLine("  not derived: " + pair.Key + " x" + pair.Value);
            var search = selection.Tolerance;
            Console.WriteLine(string.Format(CultureInfo.InvariantCulture,
                "probes kept: {0:N0} (written {1}x); search: {2:N0} probes after {3} evaluations; refinement from {4:N0} seed points, {5} commits " +
                "reported; refinement tetrahedralisations: {6}",
                selection.Indices.Length, writes.Count, search == null ? 0 : search.Count, search == null ? 0 : search.Evaluated.Count,
                selection.RefinedFrom, refinementProgress, string.Join(", ", refinementKinds)));
            Console.WriteLine("probes' fingerprint (SHA-1 of their sorted positions to the millimetre, for A/B runs): " + Fingerprint(writes[writes.Count - 1]));
            if (expected != null) Compare(writes[writes.Count - 1], expected);
        }
        (soup as IDisposable)?.Dispose();
        return 0;
    }

    /// <summary>Prints whether the probes written are <c>lpnn place</c>'s (the same positions, to the millimetre, as
    /// Tests/Core/ApplyRehearsalTests.cs compares them).</summary>
    private static void Compare(Vector3[] written, string expectedPath)
    {
        var expected = new HashSet<string>();
        foreach (var p in ProbePositionsFile.Read(expectedPath).Positions) expected.Add(Key(p));
        var got = new HashSet<string>();
        foreach (var p in written) got.Add(Key(p));
        int same = 0;
        foreach (var key in got) if (expected.Contains(key)) same++;
        Console.WriteLine(string.Format(CultureInfo.InvariantCulture, "lpnn place ({0}): {1:N0} probes; C#: {2:N0}; in common {3:N0} -> {4}",
            System.IO.Path.GetFileName(expectedPath), expected.Count, got.Count, same,
            same == expected.Count && same == got.Count ? "THE SAME PROBES" : "DIFFERENT PROBES"));
    }

    private static string Fingerprint(Vector3[] written)
    {
        var keys = new List<string>();
        foreach (var p in written) keys.Add(Key(p));
        keys.Sort(StringComparer.Ordinal);
        using (var sha = System.Security.Cryptography.SHA1.Create())
        {
            byte[] hash = sha.ComputeHash(System.Text.Encoding.UTF8.GetBytes(string.Join("\n", keys)));
            return BitConverter.ToString(hash, 0, 8).Replace("-", "").ToLowerInvariant();
        }
    }

    private static string Key(Vector3 p) => string.Format(CultureInfo.InvariantCulture, "{0:F3},{1:F3},{2:F3}", p.X, p.Y, p.Z);
}
