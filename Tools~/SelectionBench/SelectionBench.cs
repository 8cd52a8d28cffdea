using System;
using System.Collections.Generic;
using System.Diagnostics;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Selection;

/// <summary>Times the C# selection paths on synthetic n³ lattices (issue 13 item 4: none may be quadratic):
/// the score ranking, the spread ranking (a 5 % budget and the whole order), the tetrahedron guarantee on a flat
/// prefix, and the tolerance search over spread prefixes with a cheap stand-in error (a placement error in C# needs
/// Unity's tetrahedralizer, which does not run here: this times the selection side of the search only).
/// Usage: mono SelectionBench.exe [n ...] (default 22 46 100: about 10⁴, 10⁵, 10⁶ points).</summary>
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
        var sizes = new List<int>();
        foreach (var a in args) sizes.Add(int.Parse(a, System.Globalization.CultureInfo.InvariantCulture));
        if (sizes.Count == 0) sizes.AddRange(new[] { 22, 46, 100 });
        Console.WriteLine("points | build grid s | score ranking s | spread 5 % s | spread all s | tetrahedron (flat prefix) s | tolerance search s (evaluations)");
        foreach (int n in sizes)
        {
            var watch = Stopwatch.StartNew();
            var ids = new List<LatticeId>(n * n * n);
            for (int k = 0; k < n; k++)
                for (int j = 0; j < n; j++)
                    for (int i = 0; i < n; i++)
                        ids.Add(new LatticeId(i, j, k));
            var grid = EvaluationGrid.FromIds(0.5, ids);
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
        return 0;
    }
}
