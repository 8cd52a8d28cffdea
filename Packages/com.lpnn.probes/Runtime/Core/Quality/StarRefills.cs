using System;
using System.Collections.Generic;
using System.Numerics;
using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Core.Quality
{
    /// <summary>The tetrahedra that refill each candidate's star in a batched refinement trial, found without
    /// tetrahedralising the remaining probes (Documentation~/quality.md §5.3). Port of
    /// lpnn/quality/placement/trial_fills.py (star_fills).
    ///
    /// Why: a trial removes an independent set of candidates, so their stars are disjoint, and the tie-broken Delaunay
    /// tetrahedralisation is unique, so nothing outside the stars changes: each star is refilled from its own link. For a
    /// probe that is not a vertex of the hull, by gift wrapping (<see cref="HoleWrap"/>); for a hull vertex, or a hole the
    /// wrapping could not close, by the Delaunay tetrahedralisation of its link — asked of the
    /// <see cref="ITetrahedralizer"/> on those few points (<see cref="LinkTetrahedralisations"/> counts these calls; they
    /// are not tetrahedralisations of the probe set) — keeping the tetrahedra whose centroid lies in the star (the
    /// tetrahedra of Del(link) inside the star are exactly the refill). Before this the C# core tetrahedralised the whole
    /// remaining set for every trial and every commit (benchmarks.md "The C# core under Mono").
    ///
    /// Checked before use: an interior star's refill has its volume (to <see cref="VolumeTolerance"/>), a hull vertex's
    /// at most its volume; <see cref="TetrahedraAfterRemoval"/> then checks the whole (every probe used, no face in three
    /// tetrahedra, no new crack). Any failure, or a star next to a crack (a face without a tetrahedron across that is not
    /// on the hull: the star is not closed), gives null and the round tetrahedralises the remaining probes as before.
    ///
    /// Which probes are hull vertices is decided locally (trial_fills.py asks Qhull for the convex hull instead): a probe
    /// on the hull's surface is taken for a hull vertex unless its hull faces all lie in one plane or it lies between two
    /// of their vertices on one line. A wrong "vertex" only sends a star to the link's tetrahedralisation, which refills
    /// it as well.</summary>
    internal sealed class StarRefills
    {
        /// <summary>An interior star's refill must have its volume to this relative tolerance (trial_fills.py VOLUME_TOLERANCE).</summary>
        public const double VolumeTolerance = 1e-9;
        /// <summary>A refill's centroid is in the star when its barycentric weights are ≥ −this in a star tetrahedron
        /// (trial_fills.py INSIDE_TOLERANCE).</summary>
        public const double InsideTolerance = 1e-9;
        /// <summary>A boundary face lies on the hull when no probe is beyond its plane by more than this, in local units
        /// (triangulation.py HULL_SUPPORT_TOLERANCE: rounding puts hull vertices ≤ 3e-16 beyond their own faces, a crack
        /// has probes a cell or more beyond).</summary>
        public const double HullSupportTolerance = 1e-12;

        /// <summary>The trial's candidates (global point indices), independent in the probes' Delaunay graph.</summary>
        public readonly int[] Candidates;
        /// <summary>The refills: 4 global point indices per tetrahedron, positively oriented, flat ones left out.</summary>
        public readonly int[] Tetrahedra;
        /// <summary>Per refill tetrahedron, the candidate whose star it fills.</summary>
        public readonly int[] Owners;
        /// <summary>Calls made to the tetrahedraliser for links (a few points each).</summary>
        public readonly int LinkTetrahedralisations;

        private StarRefills(int[] candidates, int[] tetrahedra, int[] owners, int linkTetrahedralisations)
        {
            Candidates = candidates;
            Tetrahedra = tetrahedra;
            Owners = owners;
            LinkTetrahedralisations = linkTetrahedralisations;
        }

        /// <summary>Every candidate's refill (class text), or null when the round should tetrahedralise instead.</summary>
        /// <param name="probes">The probe set (sorted global indices) whose <paramref name="mesh"/> (indices into probes)
        /// and Delaunay graph (CSR over probe positions, global targets) are given.</param>
        /// <param name="linkCalls">Link tetrahedralisations made, also when the answer is null.</param>
        public static StarRefills Of(ReferenceLighting reference, ITetrahedralizer tetrahedralizer, int[] probes, TetrahedralMesh mesh,
            int[] edgeStart, int[] edgeTarget, int[] candidates, out int linkCalls)
        {
            linkCalls = 0;
            double[] local = reference.Local;
            double[] tie = reference.TieHeights;
            int count = candidates.Length;
            var slot = new int[probes.Length];  // probe position -> the candidate's place in `candidates`, -1 if none
            for (int k = 0; k < slot.Length; k++) slot[k] = -1;
            for (int k = 0; k < count; k++) slot[Array.BinarySearch(probes, candidates[k])] = k;
            int[] tets = mesh.Tetrahedra;
            var stars = new List<int>[count];  // star tetrahedra (mesh indices) per candidate
            for (int k = 0; k < count; k++) stars[k] = new List<int>();
            for (int t = 0; t < mesh.TetrahedronCount; t++)
                for (int j = 0; j < 4; j++)
                {
                    int k = slot[tets[4 * t + j]];
                    if (k < 0) continue;
                    stars[k].Add(t);
                    break;  // independent candidates: at most one per tetrahedron
                }
            HashSet<TriangleKey> boundary = mesh.HullFaceKeys;

            var fills = new List<int>();
            var owners = new List<int>();
            var starVolume = new double[count];
            var extreme = new bool[count];
            var filled = new bool[count];
            var starOf = new int[count][];
            for (int k = 0; k < count; k++)
            {
                int v = candidates[k];
                if (stars[k].Count == 0) return null;  // a probe the tetrahedraliser dropped
                var star = new int[4 * stars[k].Count];
                bool onSurface = false;
                var surface = new List<int>();  // the hull faces at v, global ids
                for (int s = 0; s < stars[k].Count; s++)
                {
                    int t = stars[k][s];
                    for (int j = 0; j < 4; j++) star[4 * s + j] = probes[tets[4 * t + j]];
                    starVolume[k] += Math.Abs(TetrahedralMesh.Volume6(local, star[4 * s], star[4 * s + 1], star[4 * s + 2], star[4 * s + 3], out _));
                    for (int j = 0; j < 4; j++)  // the face opposite vertex j
                    {
                        int a = tets[4 * t + (j + 1) % 4], b = tets[4 * t + (j + 2) % 4], c = tets[4 * t + (j + 3) % 4];
                        if (!boundary.Contains(new TriangleKey(a, b, c))) continue;
                        if (IsCrack(local, probes, edgeStart, edgeTarget, a, b, c, tets[4 * t + j])) return null;
                        if (probes[a] != v && probes[b] != v && probes[c] != v) continue;
                        onSurface = true;
                        surface.Add(probes[a]);
                        surface.Add(probes[b]);
                        surface.Add(probes[c]);
                    }
                }
                starOf[k] = star;
                extreme[k] = onSurface && !InsideHullFace(local, v, surface);
                if (extreme[k]) continue;
                int[] wrapped = HoleWrap.Wrap(local, tie, v, star, onSurface);
                if (wrapped == null) continue;
                int[] oriented = Oriented(local, wrapped, out double volume);
                if (!(Math.Abs(volume - starVolume[k]) <= VolumeTolerance * starVolume[k])) continue;
                filled[k] = true;
                fills.AddRange(oriented);
                for (int t = 0; t < oriented.Length / 4; t++) owners.Add(v);
            }
            for (int k = 0; k < count; k++)  // hull vertices, holes the wrapping did not close: the link's tetrahedralisation
            {
                if (filled[k]) continue;
                int[] linked = LinkFill(reference, tetrahedralizer, candidates[k], starOf[k], ref linkCalls, out double volume);
                if (linked == null) return null;
                if (volume > starVolume[k] * (1.0 + VolumeTolerance) ||
                    (!extreme[k] && Math.Abs(volume - starVolume[k]) > VolumeTolerance * starVolume[k])) return null;
                fills.AddRange(linked);
                for (int t = 0; t < linked.Length / 4; t++) owners.Add(candidates[k]);
            }
            return new StarRefills((int[])candidates.Clone(), fills.ToArray(), owners.ToArray(), linkCalls);
        }

        /// <summary>The refill tetrahedra of the given candidates (a subset of <see cref="Candidates"/>) and their owners.</summary>
        public void OfRemoved(bool[] removed, out int[] tetrahedra, out int[] owners)
        {
            var kept = new List<int>();
            var keptOwners = new List<int>();
            for (int t = 0; t < Owners.Length; t++)
            {
                if (!removed[Owners[t]]) continue;
                for (int j = 0; j < 4; j++) kept.Add(Tetrahedra[4 * t + j]);
                keptOwners.Add(Owners[t]);
            }
            tetrahedra = kept.ToArray();
            owners = keptOwners.ToArray();
        }

        /// <summary>Whether the boundary face (a, b, c) (probe positions) of a tetrahedron whose fourth vertex is
        /// <paramref name="inner"/> is a crack, not a hull face: a Delaunay neighbour of one of its corners lies beyond its
        /// plane. Beyond a crack lie the tetrahedra across the flat one that was dropped, whose far vertices are such
        /// neighbours; beyond a hull face lies no probe at all.</summary>
        private static bool IsCrack(double[] local, int[] probes, int[] edgeStart, int[] edgeTarget, int a, int b, int c, int inner)
        {
            int pa = probes[a];
            var normal = OutwardNormal(local, pa, probes[b], probes[c], probes[inner]);
            foreach (int corner in new[] { a, b, c })
                for (int e = edgeStart[corner]; e < edgeStart[corner + 1]; e++)
                    if (Beyond(local, pa, normal, edgeTarget[e]) > HullSupportTolerance) return true;
            return false;
        }

        /// <summary>The unit normal of face (a, b, c) pointing away from <paramref name="inner"/> (global ids).</summary>
        internal static Double3 OutwardNormal(double[] local, int a, int b, int c, int inner)
        {
            var n = Double3.Cross(Double3.FromTriples(local, b) - Double3.FromTriples(local, a), Double3.FromTriples(local, c) - Double3.FromTriples(local, a));
            if (Double3.Dot(n, Double3.FromTriples(local, inner) - Double3.FromTriples(local, a)) > 0) n = n * -1.0;
            return n * (1.0 / n.Length);
        }

        /// <summary>How far point q lies beyond the plane through a with unit normal n (local units).</summary>
        internal static double Beyond(double[] local, int a, Double3 n, int q) => Double3.Dot(n, Double3.FromTriples(local, q) - Double3.FromTriples(local, a));

        /// <summary>Whether v (on the hull's surface, <paramref name="surface"/> its hull faces as global id triples) is no
        /// vertex of the hull: its hull faces lie in one plane (v inside a facet) or v lies between two of their vertices
        /// on one line (inside an edge of the hull). Exact on a lattice's planes and lines (equal coordinates); anything
        /// else counts as a vertex (class text).</summary>
        private static bool InsideHullFace(double[] local, int v, List<int> surface)
        {
            var at = Double3.FromTriples(local, v);
            var normal = Double3.Cross(Double3.FromTriples(local, surface[1]) - Double3.FromTriples(local, surface[0]),
                Double3.FromTriples(local, surface[2]) - Double3.FromTriples(local, surface[0]));
            normal = normal * (1.0 / normal.Length);
            bool planar = true;
            foreach (int u in surface) planar &= Math.Abs(Double3.Dot(normal, Double3.FromTriples(local, u) - at)) <= HullSupportTolerance;
            if (planar) return true;
            var around = new List<int>();
            foreach (int u in surface)
                if (u != v && !around.Contains(u)) around.Add(u);
            for (int i = 0; i < around.Count; i++)
                for (int j = i + 1; j < around.Count; j++)
                {
                    var du = Double3.FromTriples(local, around[i]) - at;
                    var dw = Double3.FromTriples(local, around[j]) - at;
                    if (Double3.Dot(du, dw) < 0 && Double3.Cross(du, dw).Length <= HullSupportTolerance * du.Length * dw.Length) return true;
                }
            return false;
        }

        /// <summary>The tetrahedra positively oriented (the last two vertices swapped where negative), the flat ones left out
        /// as <see cref="TetrahedralMesh"/> leaves them out, and their summed 6 × volume (trial_fills.py _oriented).</summary>
        private static int[] Oriented(double[] local, int[] tetrahedra, out double volume6)
        {
            volume6 = 0;
            var kept = new List<int>(tetrahedra.Length);
            for (int t = 0; t + 3 < tetrahedra.Length; t += 4)
            {
                int a = tetrahedra[t], b = tetrahedra[t + 1], c = tetrahedra[t + 2], d = tetrahedra[t + 3];
                double det = TetrahedralMesh.Volume6(local, a, b, c, d, out bool flat);
                if (flat) continue;
                kept.Add(a);
                kept.Add(b);
                kept.Add(det < 0 ? d : c);
                kept.Add(det < 0 ? c : d);
                volume6 += Math.Abs(det);
            }
            return kept.ToArray();
        }

        /// <summary>The Delaunay tetrahedra of v's link whose centroid lies in v's star, oriented, and their 6 × volume; null
        /// when the link cannot be tetrahedralised (trial_fills.py _link_fill).</summary>
        /// <param name="calls">Counts the call to the tetrahedraliser.</param>
        private static int[] LinkFill(ReferenceLighting reference, ITetrahedralizer tetrahedralizer, int v, int[] star, ref int calls, out double volume6)
        {
            volume6 = 0;
            var distinct = new SortedSet<int>();
            foreach (int u in star)
                if (u != v) distinct.Add(u);
            var link = new int[distinct.Count];
            distinct.CopyTo(link);
            // A star of one tetrahedron (a hull vertex with three neighbours): the hull loses all of it, nothing refills it
            // (trial_fills.py _link_fill, the same rule since 2026-11-29).
            if (link.Length < 4) return new int[0];
            calls++;
            var positions = new Vector3[link.Length];
            for (int i = 0; i < link.Length; i++) positions[i] = reference.GetPosition(link[i]);
            int[] raw;
            try
            {
                raw = tetrahedralizer.Tetrahedralize(positions);
            }
            catch (Exception e) when (!(e is OperationCanceledException))
            {
                return null;  // e.g. a flat link: the whole set's tetrahedralisation decides, and reports what is wrong
            }
            if (raw == null || raw.Length == 0 || raw.Length % 4 != 0) return null;
            double[] local = reference.Local;
            var inside = new List<int>(raw.Length);
            for (int t = 0; t < raw.Length; t += 4)
            {
                var centroid = new Double3(0, 0, 0);
                for (int j = 0; j < 4; j++)
                {
                    if ((uint)raw[t + j] >= (uint)link.Length) return null;
                    centroid = centroid + Double3.FromTriples(local, link[raw[t + j]]) * 0.25;
                }
                if (!InStar(local, star, centroid)) continue;
                for (int j = 0; j < 4; j++) inside.Add(link[raw[t + j]]);
            }
            return Oriented(local, inside.ToArray(), out volume6);
        }

        /// <summary>Whether q lies (to <see cref="InsideTolerance"/> in barycentric weights) in one of the star's tetrahedra.</summary>
        private static bool InStar(double[] local, int[] star, Double3 q)
        {
            for (int s = 0; s < star.Length; s += 4)
            {
                var origin = Double3.FromTriples(local, star[s]);
                Double3 e1 = Double3.FromTriples(local, star[s + 1]) - origin, e2 = Double3.FromTriples(local, star[s + 2]) - origin,
                    e3 = Double3.FromTriples(local, star[s + 3]) - origin, r = q - origin;
                double det = Double3.Dot(e1, Double3.Cross(e2, e3));
                if (det == 0) continue;
                double w1 = Double3.Dot(r, Double3.Cross(e2, e3)) / det;
                double w2 = Double3.Dot(r, Double3.Cross(e3, e1)) / det;
                double w3 = Double3.Dot(r, Double3.Cross(e1, e2)) / det;
                if (Math.Min(w1, Math.Min(w2, w3)) >= -InsideTolerance && w1 + w2 + w3 <= 1.0 + InsideTolerance) return true;
            }
            return false;
        }
    }
}
