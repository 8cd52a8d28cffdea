using System;
using System.Collections.Generic;

namespace Lpnn.Probes.Core.Quality
{
    /// <summary>Insertion's rounds located incrementally (quality.md §5.1 step 5; Python's lpnn/quality/placement/insertion_state.py):
    /// <see cref="InsertionRanking.NextBatch"/>'s rounds, but a point keeps its tetrahedron from one round to the next.
    ///
    /// Inserting probes re-triangulates only the tetrahedra they break; every other tetrahedron is in the new
    /// tetrahedralisation too, with the same four vertices. A point inside such a tetrahedron is still inside it, so it is
    /// not located again: only its barycentric weights are computed in the new tetrahedralisation (the numbers a location
    /// that finds it there computes). Only the points whose tetrahedron broke, the points outside the hull (it may have
    /// grown) and the points on their tetrahedron's boundary (within <see cref="TetrahedronLocator.ClearlyInside"/> of a face:
    /// a face, edge or vertex it may share with another tetrahedron, where location's tie rule gives the lowest-index one,
    /// which an insertion can change; Documentation~/quality.md §1 "Ties") are located as NextBatch locates every point.
    /// Every point thus gets the stencil NextBatch gives it, and the batch is chosen exactly as NextBatch chooses it
    /// (<see cref="InsertionRanking.BatchOf"/>): the same rounds. Python's incremental rounds (insertion_state.py) follow
    /// the same rule, so both languages' rounds are a fresh location's.
    ///
    /// Each round's probes must include the previous round's (tetrahedra are matched by their four point indices, so their
    /// order is free; <see cref="InsertionOrder"/> passes them in insertion order, as a fresh round).</summary>
    internal sealed class InsertionRounds
    {
        /// <summary>Per reference point: its tetrahedron in the previous round's mesh, or -1 (a probe, outside the hull, or no
        /// previous round).</summary>
        private int[] _cellOf;
        /// <summary>The previous round's tetrahedra by their sorted point indices.</summary>
        private TetrahedronKey[] _keys;

        /// <summary>Rounds so far; over those rounds, points that kept their tetrahedron (not located) and points located (for
        /// tests and benches).</summary>
        internal int Rounds { get; private set; }
        internal long Kept { get; private set; }
        internal long Located { get; private set; }

        /// <summary><see cref="InsertionRanking.NextBatch"/> of these arguments, locating only where needed (class text).</summary>
        public int[] NextBatch(ReferenceLighting reference, int[] probes, int[] tetrahedra, double growth, double[] guide, bool[] allowed)
        {
            if (reference == null) throw new ArgumentNullException(nameof(reference));
            if (tetrahedra == null) throw new ArgumentNullException(nameof(tetrahedra));
            InsertionRanking.CheckGrowth(growth);
            InsertionRanking.CheckGuide(guide, reference.Count);
            ProbeIndices.Check(probes, reference.Count);
            var mesh = TetrahedralMesh.Build(PlacementError.ProbePoints(reference, probes), tetrahedra);
            int count = reference.Count;
            var keys = KeysOf(mesh, probes);
            var known = new int[count];
            for (int n = 0; n < count; n++) known[n] = -1;
            if (_cellOf != null && _cellOf.Length == count)
            {
                var newIndex = new Dictionary<TetrahedronKey, int>(keys.Length);
                for (int t = 0; t < keys.Length; t++) newIndex[keys[t]] = t;
                var survivor = new int[_keys.Length];
                for (int t = 0; t < survivor.Length; t++) survivor[t] = newIndex.TryGetValue(_keys[t], out int u) ? u : -1;
                for (int n = 0; n < count; n++)
                    if (_cellOf[n] >= 0) known[n] = survivor[_cellOf[n]];
            }
            var cellOf = new int[count];
            for (int n = 0; n < count; n++) cellOf[n] = -1;
            long located = 0;
            int[] batch = InsertionRanking.BatchOf(reference, probes.Length, mesh.TetrahedronCount, growth, guide, allowed,
                visit => located = PlacementError.InterpolateOthers(reference, probes, mesh, known, (int n, ref Stencil stencil, double[] interpolated) =>
                {
                    if (!stencil.Outside) cellOf[n] = stencil.Cell;
                    visit(n, ref stencil, interpolated);
                }));
            _cellOf = cellOf;
            _keys = keys;
            Rounds++;
            long others = count - probes.Length;  // every point that is not a probe was visited once (probes are distinct)
            Kept += others - located;
            Located += located;
            return batch;
        }

        /// <summary>Each tetrahedron of <paramref name="mesh"/> by the sorted reference indices of its four probes.</summary>
        private static TetrahedronKey[] KeysOf(TetrahedralMesh mesh, int[] probes)
        {
            int[] tets = mesh.Tetrahedra;
            var keys = new TetrahedronKey[mesh.TetrahedronCount];
            for (int t = 0; t < keys.Length; t++)
                keys[t] = new TetrahedronKey(probes[tets[4 * t]], probes[tets[4 * t + 1]], probes[tets[4 * t + 2]], probes[tets[4 * t + 3]]);
            return keys;
        }

        /// <summary>Four point indices, sorted.</summary>
        private struct TetrahedronKey : IEquatable<TetrahedronKey>
        {
            private readonly int _a, _b, _c, _d;

            public TetrahedronKey(int a, int b, int c, int d)
            {
                // A sorting network of five compare-exchanges.
                Order(ref a, ref b);
                Order(ref c, ref d);
                Order(ref a, ref c);
                Order(ref b, ref d);
                Order(ref b, ref c);
                _a = a;
                _b = b;
                _c = c;
                _d = d;
            }

            private static void Order(ref int x, ref int y)
            {
                if (x <= y) return;
                int swap = x;
                x = y;
                y = swap;
            }

            public bool Equals(TetrahedronKey other) => _a == other._a && _b == other._b && _c == other._c && _d == other._d;

            public override bool Equals(object obj) => obj is TetrahedronKey other && Equals(other);

            public override int GetHashCode()
            {
                unchecked
                {
                    int h = _a;
                    h = h * 486187739 + _b;
                    h = h * 486187739 + _c;
                    return h * 486187739 + _d;
                }
            }
        }
    }
}
