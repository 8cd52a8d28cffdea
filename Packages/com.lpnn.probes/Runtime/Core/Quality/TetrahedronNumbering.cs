using System;
using System.Numerics;

namespace Lpnn.Probes.Core.Quality
{
    /// <summary>The numbering of a probe set's tetrahedra that the tie rule reads (Documentation~/quality.md §1 "Ties"): a
    /// point on a face, edge or vertex shared by several tetrahedra belongs to the lowest-index one, so the numbering is
    /// part of the answer. It is made a function of the set of tetrahedra alone — not of the tetrahedraliser's order
    /// (Unity's native one, Qhull's), of the order the probes come in, or of whether the tetrahedra were tetrahedralised
    /// or derived (<see cref="RegularInsertion"/>, <see cref="InsertionTetrahedra"/>) — by ordering them by a 64-bit hash
    /// of their corners' evaluation point indices (the same in both languages; never float positions): each tetrahedron's
    /// corners ascending by point index (<see cref="TetrahedralMesh.Build"/> then orients it by swapping the last two
    /// where negative), the tetrahedra by ascending <see cref="Hash"/>, ties (never seen, but possible) by the sorted
    /// indices. Port of lpnn/quality/metric/tet_numbering.py; Tests/Data/tet_numbering_golden.json pins both.</summary>
    internal static class TetrahedronNumbering
    {
        /// <summary>splitmix64's increment, the hash's start.</summary>
        internal const ulong GoldenGamma = 0x9E3779B97F4A7C15UL;

        /// <summary>splitmix64's finaliser: a well-spread, platform-independent 64-bit mix.</summary>
        internal static ulong Mix64(ulong x)
        {
            unchecked
            {
                x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9UL;
                x = (x ^ (x >> 27)) * 0x94D049BB133111EBUL;
                return x ^ (x >> 31);
            }
        }

        /// <summary>The hash of four ascending point indices: h = Mix64(a + GoldenGamma), then h = Mix64(h ^ b), c, d.</summary>
        internal static ulong Hash(int a, int b, int c, int d)
        {
            unchecked
            {
                ulong h = Mix64((ulong)a + GoldenGamma);
                h = Mix64(h ^ (ulong)b);
                h = Mix64(h ^ (ulong)c);
                return Mix64(h ^ (ulong)d);
            }
        }

        /// <summary>The tetrahedra (4 positions in the probe set each) renumbered by the rule above: each one's corners
        /// ascending by point index <c>ids[corner]</c> (null: the positions themselves), the tetrahedra by (hash, sorted
        /// point indices). Any order of the same tetrahedra, and of their corners, gives the same array.</summary>
        internal static int[] Numbered(int[] tetrahedra, int[] ids)
        {
            if (tetrahedra == null) throw new ArgumentNullException(nameof(tetrahedra));
            int count = tetrahedra.Length / 4;
            var keys = new Key[count];
            var corners = new int[4];
            var points = new int[4];
            for (int t = 0; t < count; t++)
            {
                for (int k = 0; k < 4; k++)
                {
                    corners[k] = tetrahedra[4 * t + k];
                    points[k] = ids == null ? corners[k] : ids[corners[k]];
                }
                Array.Sort(points, corners);
                keys[t] = new Key
                {
                    Hash = Hash(points[0], points[1], points[2], points[3]),
                    P0 = points[0], P1 = points[1], P2 = points[2], P3 = points[3],
                    C0 = corners[0], C1 = corners[1], C2 = corners[2], C3 = corners[3],
                };
            }
            Array.Sort(keys, Compare);
            var result = new int[4 * count];
            for (int t = 0; t < count; t++)
            {
                result[4 * t] = keys[t].C0;
                result[4 * t + 1] = keys[t].C1;
                result[4 * t + 2] = keys[t].C2;
                result[4 * t + 3] = keys[t].C3;
            }
            return result;
        }

        /// <summary>The tetrahedraliser's tetrahedra of <paramref name="probes"/> (evaluation point indices), numbered by
        /// the rule above: every tetrahedralisation of a probe set the tie rule reads goes through here.</summary>
        internal static int[] Tetrahedralize(ITetrahedralizer tetrahedralizer, ReferenceLighting reference, int[] probes)
        {
            var positions = new Vector3[probes.Length];
            for (int k = 0; k < probes.Length; k++) positions[k] = reference.GetPosition(probes[k]);
            return Numbered(tetrahedralizer.Tetrahedralize(positions), probes);
        }

        private struct Key
        {
            public ulong Hash;
            public int P0, P1, P2, P3, C0, C1, C2, C3;
        }

        private static int Compare(Key x, Key y)
        {
            if (x.Hash != y.Hash) return x.Hash < y.Hash ? -1 : 1;
            if (x.P0 != y.P0) return x.P0.CompareTo(y.P0);
            if (x.P1 != y.P1) return x.P1.CompareTo(y.P1);
            if (x.P2 != y.P2) return x.P2.CompareTo(y.P2);
            return x.P3.CompareTo(y.P3);
        }
    }
}
