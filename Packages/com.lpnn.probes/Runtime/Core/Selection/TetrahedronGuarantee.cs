using System.Collections.Generic;
using System.Numerics;
using Lpnn.Probes.Core.Grid;

namespace Lpnn.Probes.Core.Selection
{
    /// <summary>Unity tetrahedralises light probes, so a group needs at least 4 probes not all in one plane.
    /// Adds the fewest, highest-ranked points that make one (at most 4), or explains why the grid cannot.</summary>
    internal static class TetrahedronGuarantee
    {
        /// <summary>Adds points from <paramref name="ranking"/> to <paramref name="selected"/> until it spans a
        /// tetrahedron; returns how many were added.</summary>
        public static int Ensure(EvaluationGrid grid, int[] ranking, ISet<int> selected)
        {
            int added = 0;
            if (ranking.Length == 0) throw new SelectionException("there are no evaluation points to place probes at");
            if (selected.Count == 0 && selected.Add(ranking[0])) added++;
            if (selected.Count == 1)
            {
                int second = FirstNotSelected(ranking, selected);
                if (second < 0) throw Degenerate(grid, "a single point");
                selected.Add(second);
                added++;
            }

            var chosen = new List<LatticeId>(selected.Count);
            foreach (int index in selected) chosen.Add(grid.GetId(index));
            LatticeId a = chosen[0], b = chosen[1];
            LatticeId? c = null;
            foreach (var candidate in chosen)
            {
                if (!LatticeGeometry.Collinear(a, b, candidate)) { c = candidate; break; }
            }
            if (c == null)
            {
                int offLine = FirstMatching(grid, ranking, selected, id => !LatticeGeometry.Collinear(a, b, id));
                if (offLine < 0) throw Degenerate(grid, "one line");
                selected.Add(offLine);
                added++;
                c = grid.GetId(offLine);
            }

            LatticeGeometry.Cross(a, b, c.Value, out BigInteger nx, out BigInteger ny, out BigInteger nz);
            foreach (var candidate in chosen)
                if (!LatticeGeometry.InPlane(a, nx, ny, nz, candidate)) return added;
            int offPlane = FirstMatching(grid, ranking, selected, id => !LatticeGeometry.InPlane(a, nx, ny, nz, id));
            if (offPlane < 0) throw Degenerate(grid, PlaneDescription(nx, ny, nz));
            selected.Add(offPlane);
            return added + 1;
        }

        private static int FirstNotSelected(int[] ranking, ISet<int> selected)
        {
            foreach (int index in ranking)
                if (!selected.Contains(index)) return index;
            return -1;
        }

        private static int FirstMatching(EvaluationGrid grid, int[] ranking, ISet<int> selected, System.Func<LatticeId, bool> predicate)
        {
            foreach (int index in ranking)
                if (!selected.Contains(index) && predicate(grid.GetId(index))) return index;
            return -1;
        }

        private static string PlaneDescription(BigInteger nx, BigInteger ny, BigInteger nz)
        {
            if (nx.IsZero && ny.IsZero) return "one plane (the volume is one cell thick along z)";
            if (nx.IsZero && nz.IsZero) return "one plane (the volume is one cell thick along y)";
            if (ny.IsZero && nz.IsZero) return "one plane (the volume is one cell thick along x)";
            return "one plane";
        }

        private static SelectionException Degenerate(EvaluationGrid grid, string shape) =>
            new SelectionException(
                "all " + grid.Count + " evaluation points lie in " + shape + ", and Unity needs at least 4 probes that are not " +
                "in one plane to build a tetrahedron: make the volume at least two cells deep on every axis, or use a smaller cell size");
    }
}
