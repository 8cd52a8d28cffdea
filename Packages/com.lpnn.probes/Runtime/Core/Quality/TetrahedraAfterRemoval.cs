using System.Collections.Generic;

namespace Lpnn.Probes.Core.Quality
{
    /// <summary>The tetrahedralisation of a probe set after removing some of its probes, derived from the set's own
    /// <see cref="TetrahedralMesh"/> and the removed probes' star refills (<see cref="StarRefills"/>) instead of
    /// tetrahedralising the remaining probes: the tetrahedra without a removed vertex, in their order, then the refills.
    /// Removing an independent set retriangulates the removed probes' stars and nothing else (the tie-broken Delaunay is
    /// unique), so this is the tetrahedralisation a fresh call would give, up to the order of tetrahedra and of their
    /// vertices. Port of lpnn/quality/placement/batched_state.py derived_mesh (with
    /// lpnn/quality/metric/triangulation.py assembled_after_removal).
    ///
    /// Refused (null: the caller tetrahedralises) when the result is not a tetrahedralisation of the remaining probes: a
    /// probe in no tetrahedron, a face of three tetrahedra, or a new crack — a face left without a tetrahedron across
    /// that is not on the hull (a refill that left part of a star empty). Only the faces around the stars can change, so
    /// only they are checked: such a face is on the new hull exactly when no vertex of that star's link lies beyond its
    /// plane (the tetrahedra that would cover the far side of a crack are the link's).</summary>
    internal static class TetrahedraAfterRemoval
    {
        /// <summary>A face around the stars: how many tetrahedra of the result hold it, and where its uncovered side is.</summary>
        private struct Side
        {
            public int Uses;
            public int Owner;     // the removed probe whose star the face borders
            public int Point;     // a global id on one side of the face
            public bool Covered;  // Point is on the covered side (a refill's vertex), else on the open side (the removed probe)
        }

        /// <summary>The tetrahedra of <paramref name="remaining"/> (4 indices into it each), or null (class text).</summary>
        /// <param name="probes">The set (sorted global ids) whose <paramref name="mesh"/> (indices into it) is given.</param>
        /// <param name="removed">Per global id: removed; the removed probes are independent in the mesh.</param>
        /// <param name="remaining">The sorted probes that are not removed.</param>
        /// <param name="added">The removed probes' refills: 4 global ids each, positively oriented.</param>
        /// <param name="addedOwners">Per refill tetrahedron, the removed probe whose star it fills.</param>
        public static int[] Derive(double[] local, int[] probes, TetrahedralMesh mesh, bool[] removed, int[] remaining,
            int[] added, int[] addedOwners)
        {
            var position = new int[probes.Length];  // old position -> position in remaining, -1 if removed
            int next = 0;
            for (int k = 0; k < probes.Length; k++) position[k] = removed[probes[k]] ? -1 : next++;
            if (next != remaining.Length) return null;
            HashSet<TriangleKey> boundary = mesh.HullFaceKeys;

            int[] tets = mesh.Tetrahedra;
            var result = new List<int>(tets.Length + added.Length);
            var linkFaces = new Dictionary<TriangleKey, Side>();  // faces opposite a removed probe, with a kept tetrahedron across
            var links = new Dictionary<int, List<int>>();  // removed probe -> its link (global ids)
            var between = new Dictionary<TriangleKey, int[]>();  // faces between two removed stars -> their two probes
            for (int t = 0; t < mesh.TetrahedronCount; t++)
            {
                int gone = -1;
                for (int j = 0; j < 4; j++)
                    if (position[tets[4 * t + j]] < 0)
                    {
                        if (gone >= 0) return null;  // two removed probes share a tetrahedron: not independent
                        gone = j;
                    }
                if (gone < 0)
                {
                    for (int j = 0; j < 4; j++) result.Add(position[tets[4 * t + j]]);
                    continue;
                }
                int v = probes[tets[4 * t + gone]];
                if (!links.TryGetValue(v, out var link)) links[v] = link = new List<int>();
                int a = tets[4 * t + (gone + 1) % 4], b = tets[4 * t + (gone + 2) % 4], c = tets[4 * t + (gone + 3) % 4];
                foreach (int u in new[] { a, b, c })
                    if (!link.Contains(probes[u])) link.Add(probes[u]);
                if (boundary.Contains(new TriangleKey(a, b, c))) continue;  // nothing across
                var key = new TriangleKey(position[a], position[b], position[c]);
                if (linkFaces.TryGetValue(key, out var first))  // the face parts two removed stars: each side is a refill's
                {
                    linkFaces.Remove(key);
                    between[key] = new[] { first.Owner, v };
                }
                else linkFaces[key] = new Side { Uses = 1, Owner = v, Point = v, Covered = false };
            }
            var faces = new Dictionary<TriangleKey, Side>(linkFaces);
            for (int t = 0; t + 3 < added.Length; t += 4)
            {
                var at = new int[4];
                for (int j = 0; j < 4; j++)
                {
                    at[j] = System.Array.BinarySearch(remaining, added[t + j]);
                    if (at[j] < 0) return null;  // a refill with a removed or unknown vertex
                    result.Add(at[j]);
                }
                for (int j = 0; j < 4; j++)
                {
                    var key = new TriangleKey(at[(j + 1) % 4], at[(j + 2) % 4], at[(j + 3) % 4]);
                    if (faces.TryGetValue(key, out var side)) side.Uses++;
                    else side = new Side { Uses = 1, Owner = addedOwners[t / 4], Point = added[t + j], Covered = true };
                    faces[key] = side;
                }
            }
            foreach (var pair in faces)
            {
                var side = pair.Value;
                if (side.Uses > 2) return null;  // not a manifold
                if (side.Uses == 2) continue;
                if (!links.TryGetValue(side.Owner, out var link)) return null;
                // A face between two stars refilled on one side only: what lies beyond it was the other star's, whose link
                // holds the vertices of whatever covers it (on the hull when a hull vertex went: nothing does).
                if (between.TryGetValue(pair.Key, out int[] stars)) link = links[stars[0] == side.Owner ? stars[1] : stars[0]];
                int a = remaining[pair.Key.A];
                var normal = StarRefills.OutwardNormal(local, a, remaining[pair.Key.B], remaining[pair.Key.C], side.Point);
                if (!side.Covered) normal = normal * -1.0;  // the open side is the removed probe's
                foreach (int u in link)
                    if (StarRefills.Beyond(local, a, normal, u) > StarRefills.HullSupportTolerance) return null;  // a new crack
            }
            var used = new bool[remaining.Length];
            foreach (int p in result) used[p] = true;
            foreach (bool u in used)
                if (!u) return null;
            return result.ToArray();
        }
    }
}
