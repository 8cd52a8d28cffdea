using System;
using System.Collections.Generic;
using Lpnn.Probes.Core.Grid;

namespace Lpnn.Probes.Core.Selection
{
    /// <summary>The probes chosen from a grid: point indices sorted ascending, and what was added on top of
    /// the policy to keep the bounds corners and to guarantee a tetrahedron.</summary>
    public sealed class SelectionResult
    {
        public int[] Indices { get; }
        public int CornersAdded { get; }
        public int AddedForTetrahedron { get; }

        public SelectionResult(int[] indices, int cornersAdded, int addedForTetrahedron)
        {
            Indices = indices;
            CornersAdded = cornersAdded;
            AddedForTetrahedron = addedForTetrahedron;
        }
    }

    /// <summary>Applies a selection policy to per-point scores (Documentation~/selection.md).</summary>
    public static class ProbeSelector
    {
        /// <summary>K = floor((1 − p)·N + 0.5 + 1e-9): "0.9 keeps the top 10 %", rounded to the nearest point, halves
        /// up; the 1e-9 absorbs binary rounding ((1 − 0.9)·125 + 0.5 is 12.999… in double).</summary>
        public static int PercentileCount(double percentile, int pointCount)
        {
            SelectionSettings.Percentile(percentile).Validate();
            return (int)Math.Floor((1 - percentile) * pointCount + 0.5 + 1e-9);
        }

        public static SelectionResult Select(EvaluationGrid grid, float[] scores, SelectionSettings settings)
        {
            if (grid == null) throw new ArgumentNullException(nameof(grid));
            if (scores == null || scores.Length != grid.Count)
                throw new SelectionException("need one score per evaluation point: got " + (scores?.Length ?? 0) + " scores for " + grid.Count + " points");
            settings.Validate();
            int[] ranking = ScoreRanking.Rank(scores);
            var selected = new HashSet<int>();
            switch (settings.Policy)
            {
                case SelectionPolicy.Percentile:
                    AddTop(ranking, PercentileCount(settings.Value, grid.Count), selected);
                    break;
                case SelectionPolicy.Budget:
                    AddTop(ranking, (int)Math.Min(settings.Value, grid.Count), selected);
                    break;
                default:
                    double[] remapped = ScoreRanking.Remap(scores);
                    for (int n = 0; n < grid.Count; n++)
                        if (!float.IsNaN(scores[n]) && remapped[n] >= settings.Value) selected.Add(n);
                    break;
            }
            int corners = settings.KeepBoundsCorners ? AddCorners(grid, selected) : 0;
            int added = TetrahedronGuarantee.Ensure(grid, ranking, selected);
            var indices = new int[selected.Count];
            selected.CopyTo(indices);
            Array.Sort(indices);
            return new SelectionResult(indices, corners, added);
        }

        private static void AddTop(int[] ranking, int count, ISet<int> selected)
        {
            for (int r = 0; r < count; r++) selected.Add(ranking[r]);
        }

        /// <summary>The grid point whose cell holds each box corner (a grid point unless a filter such as "drop
        /// points inside walls" removed it, in which case that corner is skipped); returns how many were added.</summary>
        private static int AddCorners(EvaluationGrid grid, ISet<int> selected)
        {
            if (grid.Boxes.Count == 0)
                throw new SelectionException("this grid was rebuilt from stored ids and has no boxes, so the bounds corners are unknown; turn off 'keep bounds corners'");
            int added = 0;
            foreach (var box in grid.Boxes)
            {
                for (int c = 0; c < 8; c++)
                {
                    var corner = box.Corner(c);
                    int index = LatticeId.TryCellOf(corner, grid.CellSize, out var id) ? grid.IndexOf(id) : -1;
                    if (index >= 0 && selected.Add(index)) added++;
                }
            }
            return added;
        }
    }
}
