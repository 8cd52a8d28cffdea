using System;
using System.Collections.Generic;
using System.Diagnostics;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Quality;
using Lpnn.Probes.Core.Selection;
using Lpnn.Probes.Core.Tests.Support;

/// <summary>Times the C# selection paths on synthetic n³ lattices (issue 13 item 4: none may be quadratic):
/// the score ranking, the spread ranking (a 5 % budget and the whole order), the tetrahedron guarantee on a flat
/// prefix, and the tolerance search over spread prefixes with a cheap stand-in error (a placement error in C# needs
/// Unity's tetrahedralizer, which does not run here: this times the selection side of the search only).
/// Then the parts of the insertion ranking (Quality.InsertionRanking) that run without Unity: the reference lighting, the
/// typical tetrahedron, and one round given a mesh (the Freudenthal–Kuhn tetrahedra of the stride-4 sub-lattice as the
/// probes' mesh). The whole ranking tetrahedralises the probes every round with Unity's tetrahedraliser; the tests' own
/// Delaunay is O(n²) per call, so the whole ranking's time can only be measured in Unity.
/// Last, one round of the batched refinement (Quality.BatchedRefinement), whose Unity-independent part is linear in the points.
/// Usage: mono SelectionBench.exe [--batched] [n ...] (default 22 46 100: about 10⁴, 10⁵, 10⁶ points; --batched: only
/// the batched refinement round); mono SelectionBench.exe --apply CAPTURE SCRIPT [--geometry TRIANGLES.bin | --embree
/// SERVER.sh] [--no-memo] [--no-refills] [--expect PROBES.json]: the whole default selection on a real capture with Python's
/// tetrahedraliser, leak-aware over the level's triangles (C#) or Python's Embree when given either, compared with lpnn
/// place's probes when given them (<see cref="ApplyBench"/>).</summary>
public static class SelectionBench
{
    /// <summary>Stands in for the placement error: τ·(K/count), so the search settles on K = 5 % of the points after
    /// its usual ~2·log₂N evaluations, each prefix completed to a tetrahedron like a real one.</summary>
    private sealed class FallingError : IPlacementErrorMeasure
    {
        private readonly double _answer;
        public FallingError(int pointCount) { _answer = Math.Max(4, pointCount / 20); }
        public double MeanError(int[] probeIndices) => Tolerance * _answer / probeIndices.Length;
    }

    private const double Tolerance = 0.02;

    public static int Main(string[] args)
    {
        if (args.Length > 0 && args[0] == "--apply")
        {
            const string usage = "usage: SelectionBench.exe --apply CAPTURE TETRAHEDRALIZER.sh [--geometry TRIANGLES.bin | --embree SERVER.sh] [--no-memo] " +
                                 "[--no-refills] [--tetrahedralised-rounds] [--serial] [--expect PROBES.json]";
            if (args.Length < 3) throw new ArgumentException(usage);
            string geometry = null, embree = null, expected = null;
            bool remember = true, refills = true;
            var meshes = InsertionTetrahedra.Mode.Derived;
            for (int a = 3; a < args.Length; a++)
            {
                if (args[a] == "--geometry" && a + 1 < args.Length) geometry = args[++a];
                else if (args[a] == "--embree" && a + 1 < args.Length) embree = args[++a];
                else if (args[a] == "--expect" && a + 1 < args.Length) expected = args[++a];
                else if (args[a] == "--no-memo") remember = false;
                else if (args[a] == "--no-refills") refills = false;
                else if (args[a] == "--serial") Lpnn.Probes.Core.Numerics.ParallelChunks.ForcedChunks = 1;  // this (the Apply's) thread's passes on one core
                else if (args[a] == "--tetrahedralised-rounds") meshes = InsertionTetrahedra.Mode.Tetrahedralised;
                else throw new ArgumentException(usage + "; got " + args[a]);
            }
            if (geometry != null && embree != null) throw new ArgumentException("--geometry or --embree, not both");
            if (!remember && geometry == null && embree == null) throw new ArgumentException("--no-memo needs --geometry or --embree (the leak-aware Apply)");
            return ApplyBench.Run(args[1], args[2], ApplyBench.Tolerance, geometry, embree, remember, expected, refills, meshes);
        }
        var sizes = new List<int>();
        bool batchedOnly = false;
        foreach (var a in args)
        {
            if (a == "--batched") batchedOnly = true;
            else sizes.Add(int.Parse(a, System.Globalization.CultureInfo.InvariantCulture));
        }
        if (sizes.Count == 0) sizes.AddRange(new[] { 22, 46, 100 });
        if (batchedOnly)
        {
            BatchedRounds(sizes);
            return 0;
        }
        Console.WriteLine("points | build grid s | score ranking s | spread 5 % s | spread all s | tetrahedron (flat prefix) s | tolerance search s (evaluations)");
        foreach (int n in sizes)
        {
            var watch = Stopwatch.StartNew();
            var grid = Lattice(n);
            double build = watch.Elapsed.TotalSeconds;
            int count = grid.Count;
            var random = new Random(1);
            var scores = new float[count];
            for (int p = 0; p < count; p++) scores[p] = (float)random.NextDouble();

            watch.Restart();
            int[] scoreOrder = ScoreRanking.Rank(scores);
            double scoreSeconds = watch.Elapsed.TotalSeconds;
            watch.Restart();
            SpreadRanking.Rank(grid, scores, count / 20);
            double budgetSeconds = watch.Elapsed.TotalSeconds;
            watch.Restart();
            int[] spread = SpreadRanking.Rank(grid, scores);
            double allSeconds = watch.Elapsed.TotalSeconds;

            // A prefix in one plane (the whole k = 0 layer): the guarantee must find an off-plane point.
            var flat = new HashSet<int>();
            for (int p = 0; p < n * n; p++) flat.Add(p);
            watch.Restart();
            int added = TetrahedronGuarantee.Ensure(grid, scoreOrder, flat);
            double tetraSeconds = watch.Elapsed.TotalSeconds;
            if (added != 1) throw new InvalidOperationException("expected one point added off the plane, got " + added);

            watch.Restart();
            var result = ProbeSelector.WithinTolerance(grid, spread, SelectionSettings.Tolerance(Tolerance), new FallingError(count));
            double toleranceSeconds = watch.Elapsed.TotalSeconds;
            Console.WriteLine(string.Format(System.Globalization.CultureInfo.InvariantCulture,
                "{0:N0} | {1:F2} | {2:F2} | {3:F2} | {4:F2} | {5:F3} | {6:F2} ({7})",
                count, build, scoreSeconds, budgetSeconds, allSeconds, tetraSeconds, toleranceSeconds, result.Tolerance.Evaluated.Count));
        }
        Console.WriteLine();
        Console.WriteLine("points | reference lighting s | typical tetrahedron s | one insertion round given the mesh s (probes, tetrahedra, batch)");
        foreach (int n in sizes) InsertionParts(n);
        Console.WriteLine();
        BatchedRounds(sizes);
        return 0;
    }

    private static void BatchedRounds(List<int> sizes)
    {
        Console.WriteLine("points | one batched refinement round s (the seed evaluated at every point, the trial at the candidates' points, " +
                          "the commit at its probe's; the tests' Delaunay) | seed probes");
        foreach (int n in sizes) BatchedRound(n);
    }

    /// <summary>One round of Quality.BatchedRefinement from the 5 × 5 × 5 sub-lattice: ToCount(seed, |seed| − 1) runs exactly
    /// one round (its first commit reaches the count). Its cost besides the tetrahedralisations is the seed's interpolation
    /// of every point, the trial's at the points whose stencil weighs a candidate, the commit's at the points whose stencil
    /// touched the removed probe, the Delaunay graph and the sorts; with 125 probes the tests' O(P²) Delaunay is negligible,
    /// so this times the part that grows with the points.</summary>
    private static void BatchedRound(int n)
    {
        var grid = Lattice(n);
        var reference = ReferenceLighting.FromGrid(grid, SyntheticSh(grid));
        int[] seed = QualityFixtures.LatticeProbes(grid, Math.Max(1, (n - 1) / 4));
        var watch = Stopwatch.StartNew();
        var result = BatchedRefinement.ToCount(reference, new BowyerWatsonDelaunay(), seed, seed.Length - 1);
        double seconds = watch.Elapsed.TotalSeconds;
        if (result.Rounds != 1) throw new InvalidOperationException("expected one round, got " + result.Rounds);
        Console.WriteLine(string.Format(System.Globalization.CultureInfo.InvariantCulture, "{0:N0} | {1:F2} | {2}", grid.Count, seconds, seed.Length));
    }

    /// <summary>The n³ lattice at cell 0.5, in grid order.</summary>
    private static EvaluationGrid Lattice(int n)
    {
        var ids = new List<LatticeId>(n * n * n);
        for (int k = 0; k < n; k++)
            for (int j = 0; j < n; j++)
                for (int i = 0; i < n; i++)
                    ids.Add(new LatticeId(i, j, k));
        return EvaluationGrid.FromIds(0.5, ids);
    }

    /// <summary>Smooth synthetic lighting (two waves and a bright corner), so every cell has a clear worst point.</summary>
    private static float[] SyntheticSh(EvaluationGrid grid)
    {
        var sh = new float[27 * grid.Count];
        for (int p = 0; p < grid.Count; p++)
        {
            var x = grid.GetPosition(p);
            double wave = 1.0 + 0.5 * Math.Sin(0.7 * x.X) * Math.Cos(0.4 * x.Z) + 2.0 / (1.0 + x.LengthSquared());
            for (int c = 0; c < 27; c++)
                sh[27 * p + c] = (float)(c % 9 == 0 ? wave * (1.0 - 0.2 * (c / 9)) : 0.1 * wave * Math.Sin(c + 0.3 * x.Y));
        }
        return sh;
    }

    private static void InsertionParts(int n)
    {
        var grid = Lattice(n);
        float[] sh = SyntheticSh(grid);
        var watch = Stopwatch.StartNew();
        var reference = ReferenceLighting.FromGrid(grid, sh);
        double referenceSeconds = watch.Elapsed.TotalSeconds;
        watch.Restart();
        InsertionRanking.TypicalTetrahedron(grid, reference);
        double typicalSeconds = watch.Elapsed.TotalSeconds;
        const int stride = 4;
        int[] probes = QualityFixtures.LatticeProbes(grid, stride);
        int side = (n - 1) / stride + 1;
        int[] tetrahedra = QualityFixtures.KuhnTetrahedra(side, side, side);
        watch.Restart();
        int[] batch = InsertionRanking.NextBatch(reference, probes, tetrahedra);
        double roundSeconds = watch.Elapsed.TotalSeconds;
        Console.WriteLine(string.Format(System.Globalization.CultureInfo.InvariantCulture, "{0:N0} | {1:F2} | {2:F2} | {3:F2} ({4:N0}, {5:N0}, {6:N0})",
            grid.Count, referenceSeconds, typicalSeconds, roundSeconds, probes.Length, tetrahedra.Length / 4, batch.Length));
    }
}
