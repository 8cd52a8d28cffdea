using System.Collections.Generic;

namespace Lpnn.Probes.Core.Quality
{
    /// <summary>One probe set of <see cref="BatchedRefinement"/> evaluated (Documentation~/quality.md §5.3): per point its
    /// error, the probes its stencil weighs and every probe its stencil touches; the tetrahedra and their Delaunay graph;
    /// the error sum. A trial (<see cref="RemovalCosts"/>) is interpolated only at the points whose stencil weighs a
    /// candidate, and the set without some probes (<see cref="Without"/>) only at the points whose stencil touched one:
    /// the tie-broken Delaunay is unique, so every other tetrahedron survives a removal, and a point outside the shrinking
    /// hull keeps its nearest hull point unless that point's triangle had a removed vertex. For the same reason neither
    /// tetrahedralises the remaining probes: the trial refills each candidate's star from its link
    /// (<see cref="StarRefills"/>) and both derive their tetrahedra from this set's and the refills
    /// (<see cref="TetrahedraAfterRemoval"/>); only when a refill or the result is refused is the set tetrahedralised
    /// (the <see cref="ITetrahedralizer"/>, Unity's native one in the editor). Port of
    /// lpnn/quality/placement/batched_state.py. With a <see cref="LeakWeighting"/> every error the state holds, sums and
    /// compares is the weighted one, and trials and removals keep it, as the Python state does.</summary>
    internal sealed class BatchedRefinementState
    {
        internal int[] Probes;      // sorted evaluation point indices
        internal double[] Errors;   // per point, 0 at the probes
        internal int[] Owners;      // 4 per point: the probes (point indices) its stencil weighs > 0, else -1
        internal int[] Touched;     // 4 per point: every probe (point index) of its stencil, zero weights included; -1 at probes
        internal int[] EdgeStart;   // CSR over Probes' positions: neighbours of Probes[k] in EdgeStart[k]..EdgeStart[k+1]
        internal int[] EdgeTarget;  // neighbour point indices
        internal double ErrorSum;
        internal LeakWeighting Leaks;  // null: plain errors
        internal TetrahedralMesh Mesh;  // the probes' tetrahedra (indices into Probes)
        internal RefillCounts Counts;  // shared by every state of one refinement

        /// <summary>The last trial's refills (null: it was tetrahedralised, or none was made), from which <see cref="Without"/>
        /// derives the committed set's tetrahedra.</summary>
        private StarRefills trialRefills;
        /// <summary>Whether a trial was made on this set (<see cref="RemovalCosts"/>): a round whose candidates all kept
        /// their fresh costs makes none, and its commit then refills the removed probes' stars itself.</summary>
        private bool trialMade;

        /// <summary>Tests and the Apply bench's --no-refills only: every trial and commit tetrahedralises the remaining
        /// probes, as before the refills (the refinement must then keep the same probes). Per thread, so that a test cannot
        /// leak it into another's run.</summary>
        [System.ThreadStatic] internal static bool ForceTetrahedralisation;

        /// <summary>What the refills saved and cost in one refinement.</summary>
        internal sealed class RefillCounts
        {
            /// <summary>Trials and commits whose tetrahedra were derived from refills.</summary>
            public int Derived;
            /// <summary>Trials and commits that tetrahedralised the remaining probes (a refill or its result refused).</summary>
            public int Tetrahedralised;
            /// <summary>Tetrahedralisations of a single star's link (a few points each, <see cref="StarRefills"/>).</summary>
            public int LinkTetrahedralisations;
            /// <summary>The comparisons of trials derived from refills with the tetrahedraliser's own tetrahedra for the
            /// same probes (<see cref="DerivationCheck"/>): until one agrees, every derived trial is compared (one call),
            /// and one that disagrees takes the tetrahedraliser's answer and its commit is tetrahedralised, so the next
            /// trial derives from the tetrahedraliser's tetrahedra again instead of giving up deriving — a degenerate
            /// star's refill differs now and then (ctf@0.81, 10^6 points); after
            /// <see cref="DerivationCheck.MaxResyncs"/> disagreements before any agreement the refinement tetrahedralises
            /// every set as before.</summary>
            public readonly DerivationCheck Check = new DerivationCheck();
        }

        /// <summary>Each candidate's removal cost into <paramref name="cost"/>: the summed error change (ascending point
        /// order) at the points whose stencil weighed it, plus its own new error. The trial (<paramref name="remaining"/>:
        /// the probes without the candidates) is interpolated at those points only.</summary>
        internal void RemovalCosts(ReferenceLighting reference, ITetrahedralizer tetrahedralizer, int[] remaining,
            int[] candidates, double[] cost)
        {
            int n = reference.Count;
            var isCandidate = new bool[n];
            foreach (int c in candidates) isCandidate[c] = true;
            foreach (int c in candidates) cost[c] = 0.0;
            var owner = new int[n];
            var attributed = new List<int>();
            for (int p = 0; p < n; p++)
            {
                owner[p] = isCandidate[p] ? p : -1;
                for (int k = 0; k < 4 && owner[p] < 0; k++)
                {
                    int o = Owners[4 * p + k];
                    if (o >= 0 && isCandidate[o]) owner[p] = o;
                }
                if (owner[p] >= 0) attributed.Add(p);
            }
            var trialErrors = new double[n];
            var seen = Leaks == null ? null : new StencilLog();
            trialMade = true;
            var trial = RefilledTrial(reference, tetrahedralizer, remaining, candidates, isCandidate) ?? Tetrahedralize(reference, tetrahedralizer, remaining);
            PlacementError.InterpolatePoints(reference, remaining, trial, attributed.ToArray(),
                (int p, ref Stencil stencil, double[] interpolated) => trialErrors[p] = PointError(reference, p, interpolated),
                seen?.Visitor);
            if (seen != null) Leaks.Weigh(reference, remaining, seen, trialErrors);
            foreach (int p in attributed) cost[owner[p]] += trialErrors[p] - Errors[p];
        }

        /// <summary>The trial's tetrahedra from the candidates' star refills (kept for <see cref="Without"/>), or null when
        /// a refill or the result is refused (or <see cref="ForceTetrahedralisation"/>). <paramref name="isCandidate"/>: the
        /// candidates flagged per point (read only).</summary>
        private TetrahedralMesh RefilledTrial(ReferenceLighting reference, ITetrahedralizer tetrahedralizer, int[] remaining, int[] candidates,
            bool[] isCandidate)
        {
            trialRefills = null;
            if (ForceTetrahedralisation || !Counts.Check.Derives) return null;
            var refills = StarRefills.Of(reference, tetrahedralizer, Probes, Mesh, EdgeStart, EdgeTarget, candidates, out int linkCalls);
            Counts.LinkTetrahedralisations += linkCalls;
            if (refills == null) return null;
            var mesh = Derived(reference, isCandidate, remaining, refills.Tetrahedra, refills.Owners);
            if (mesh == null) return null;
            if (Counts.Check.Compares)  // until one agrees: one more tetrahedralisation (RefillCounts.Check)
            {
                var fresh = Tetrahedralize(reference, tetrahedralizer, remaining);
                if (!Counts.Check.Record(mesh.HasTheTetrahedraOf(fresh)))
                    return fresh;  // trialRefills stays null: the commit is tetrahedralised, and the next trial derives from it
            }
            trialRefills = refills;
            return mesh;
        }

        /// <summary>The mesh of <paramref name="remaining"/> from this set's tetrahedra and the refills of the
        /// <paramref name="removed"/> probes' stars, or null when <see cref="TetrahedraAfterRemoval"/> or the mesh
        /// refuses them. Counted either way.</summary>
        private TetrahedralMesh Derived(ReferenceLighting reference, bool[] removed, int[] remaining, int[] added, int[] owners)
        {
            int[] tetrahedra = TetrahedraAfterRemoval.Derive(reference.Local, Probes, Mesh, removed, remaining, added, owners);
            TetrahedralMesh mesh = null;
            if (tetrahedra != null)
            {
                try
                {
                    mesh = TetrahedralMesh.Build(PlacementError.ProbePoints(reference, remaining), tetrahedra);
                }
                catch (PlacementErrorException)
                {
                    mesh = null;  // e.g. a face in three tetrahedra: tetrahedralise instead
                }
            }
            if (mesh != null) Counts.Derived++;
            return mesh;
        }

        /// <summary>The sorted <paramref name="probes"/> without <paramref name="removed"/>, in order.</summary>
        internal static int[] ProbesWithout(int[] probes, int[] removed, int n)
        {
            var gone = new bool[n];
            foreach (int r in removed) gone[r] = true;
            var kept = new List<int>(probes.Length);
            foreach (int p in probes)
                if (!gone[p]) kept.Add(p);
            return kept.ToArray();
        }

        /// <summary>Every point of <paramref name="probes"/> (sorted) evaluated: the seed.</summary>
        /// <param name="leaks">Weighs leaking points' errors from now on (null: plain errors).</param>
        internal static BatchedRefinementState Evaluate(ReferenceLighting reference, ITetrahedralizer tetrahedralizer, int[] probes,
            LeakWeighting leaks = null)
        {
            int n = reference.Count;
            var state = new BatchedRefinementState
            {
                Probes = probes, Errors = new double[n], Owners = new int[4 * n], Touched = new int[4 * n], Leaks = leaks,
                Counts = new RefillCounts()
            };
            for (int i = 0; i < 4 * n; i++) state.Owners[i] = state.Touched[i] = -1;
            Relocate(reference, state, state.Tetrahedralize(reference, tetrahedralizer, probes), null);
            return state;
        }

        /// <summary>The state of these probes without <paramref name="removed"/>: only the points whose
        /// stencil touched a removed probe (and the removed themselves) are interpolated again, through tetrahedra derived
        /// from the last trial's refills when <paramref name="removed"/> are among its candidates (class text).</summary>
        internal BatchedRefinementState Without(ReferenceLighting reference, ITetrahedralizer tetrahedralizer, int[] removed)
        {
            int n = reference.Count;
            var gone = new bool[n];
            foreach (int r in removed) gone[r] = true;
            var affected = new List<int>();
            for (int p = 0; p < n; p++)
            {
                bool touched = gone[p];
                for (int k = 0; k < 4 && !touched; k++)
                {
                    int o = Touched[4 * p + k];
                    touched = o >= 0 && gone[o];
                }
                if (touched) affected.Add(p);
            }
            var next = new BatchedRefinementState
            {
                Probes = ProbesWithout(Probes, removed, n), Errors = (double[])Errors.Clone(),
                Owners = (int[])Owners.Clone(), Touched = (int[])Touched.Clone(), Leaks = Leaks, Counts = Counts
            };
            TetrahedralMesh mesh = null;
            if (RemovalRefills(reference, tetrahedralizer, removed, gone, out int[] added, out int[] owners))
                mesh = Derived(reference, gone, next.Probes, added, owners);
            Relocate(reference, next, mesh ?? Tetrahedralize(reference, tetrahedralizer, next.Probes), affected.ToArray());
            return next;
        }

        /// <summary>The refills of the <paramref name="removed"/> probes' stars (<paramref name="gone"/>: them, flagged per
        /// point) and the probe each fills: the last trial's, and for the removed probes it did not refill (candidates that
        /// kept their fresh costs, <see cref="BoundaryVertices"/>) refills made now — when the trial was not
        /// tetrahedralised, or no trial was made and derived sets are trusted (<see cref="DerivationCheck.Agrees"/>). False
        /// when the set must be tetrahedralised (after a disagreement the commit re-synchronises; a refill refused).</summary>
        private bool RemovalRefills(ReferenceLighting reference, ITetrahedralizer tetrahedralizer, int[] removed, bool[] gone,
            out int[] added, out int[] owners)
        {
            added = owners = null;
            var lacking = new List<int>();
            var inTrial = new bool[gone.Length];
            if (trialRefills != null)
                foreach (int c in trialRefills.Candidates) inTrial[c] = true;
            foreach (int r in removed)
                if (!inTrial[r]) lacking.Add(r);
            if (lacking.Count > 0)
            {
                bool trusted = trialMade ? trialRefills != null : Counts.Check.Agrees;
                if (!trusted || ForceTetrahedralisation || !Counts.Check.Derives) return false;
            }
            else if (trialRefills == null) return false;
            var parts = new List<StarRefills>();
            if (trialRefills != null) parts.Add(trialRefills);
            if (lacking.Count > 0)
            {
                int[] made = lacking.ToArray();
                var refills = StarRefills.Of(reference, tetrahedralizer, Probes, Mesh, EdgeStart, EdgeTarget, made, out int linkCalls);
                Counts.LinkTetrahedralisations += linkCalls;
                if (refills == null) return false;
                parts.Add(refills);
            }
            var allAdded = new List<int>();
            var allOwners = new List<int>();
            foreach (var part in parts)
            {
                part.OfRemoved(gone, out int[] partAdded, out int[] partOwners);
                allAdded.AddRange(partAdded);
                allOwners.AddRange(partOwners);
            }
            added = allAdded.ToArray();
            owners = allOwners.ToArray();
            return true;
        }

        /// <summary>Per point, whether it is a probe on a face with no tetrahedron across (the hull's, or a crack's:
        /// <see cref="TetrahedralMesh.HullFaces"/>). Any other probe's fresh cost (measured, no Delaunay neighbour removed
        /// since) is what a new trial would measure, up to rounding: its star, the points in it, their old errors and its
        /// refill (a function of its link) are unchanged, and other candidates' removals leave the hull it lies inside
        /// alone. A boundary probe's is not: the points of its star that fall outside the shrunken hull project onto a
        /// hull that removals elsewhere may have changed (<see cref="BatchedRefinement"/> step 2; Python
        /// batched_state.boundary_vertices).</summary>
        internal bool[] BoundaryVertices(int n)
        {
            var on = new bool[n];
            foreach (int v in Mesh.HullFaces) on[Probes[v]] = true;
            return on;
        }

        /// <summary>Interpolates <paramref name="points"/> (ascending, none a probe; null: every point that is not a probe)
        /// through <paramref name="mesh"/> (the state's probes') into its errors, owners and touched probes; then its
        /// edges and error sum.</summary>
        private static void Relocate(ReferenceLighting reference, BatchedRefinementState state, TetrahedralMesh mesh, int[] points)
        {
            int[] probes = state.Probes;
            state.Mesh = mesh;
            double[] errors = state.Errors;
            int[] owners = state.Owners, touched = state.Touched;
            var seen = state.Leaks == null ? null : new StencilLog();
            PlacementError.InterpolatePoints(reference, probes, mesh, points, (int p, ref Stencil stencil, double[] interpolated) =>
            {
                errors[p] = PointError(reference, p, interpolated);
                touched[4 * p] = probes[stencil.Probe0];
                touched[4 * p + 1] = probes[stencil.Probe1];
                touched[4 * p + 2] = probes[stencil.Probe2];
                touched[4 * p + 3] = probes[stencil.Probe3];
                owners[4 * p] = stencil.Weight0 > 0 ? touched[4 * p] : -1;
                owners[4 * p + 1] = stencil.Weight1 > 0 ? touched[4 * p + 1] : -1;
                owners[4 * p + 2] = stencil.Weight2 > 0 ? touched[4 * p + 2] : -1;
                owners[4 * p + 3] = stencil.Weight3 > 0 ? touched[4 * p + 3] : -1;
            }, seen?.Visitor);
            if (seen != null) state.Leaks.Weigh(reference, probes, seen, errors);
            double sum = 0;
            foreach (double e in errors) sum += e;
            state.ErrorSum = sum;
            Edges(mesh.Tetrahedra, probes, out state.EdgeStart, out state.EdgeTarget);
        }

        /// <summary>The probes tetrahedralised as a whole (the seed; a trial or commit whose refills were refused).</summary>
        private TetrahedralMesh Tetrahedralize(ReferenceLighting reference, ITetrahedralizer tetrahedralizer, int[] probes)
        {
            Counts.Tetrahedralised++;
            ProbeIndices.Check(probes, reference.Count);
            return TetrahedralMesh.Build(PlacementError.ProbePoints(reference, probes), TetrahedronNumbering.Tetrahedralize(tetrahedralizer, reference, probes));
        }

        private static double PointError(ReferenceLighting reference, int p, double[] interpolated) =>
            PointErrorMetrics.Irradiance(interpolated, reference.Light, p * ReferenceLighting.LightValues, reference.SceneScale);

        /// <summary>The Delaunay graph as CSR over the probe list: each tetrahedron's 6 edges, both ways, without repeats.</summary>
        private static void Edges(int[] tetrahedra, int[] probes, out int[] start, out int[] target)
        {
            // Each probe's neighbours gathered from the tetrahedra at it (no sort of all 12 ordered pairs per tetrahedron,
            // which Mono's List.Sort made a tenth of the refinement): each row distinct, ascending, as the pairs' sort gave.
            int count = probes.Length;
            var atStart = new int[count + 1];
            foreach (int v in tetrahedra) atStart[v + 1]++;
            for (int k = 0; k < count; k++) atStart[k + 1] += atStart[k];
            var at = new int[tetrahedra.Length];  // per probe, its tetrahedra's offsets (4 × index)
            var filled = (int[])atStart.Clone();
            for (int i = 0; i < tetrahedra.Length; i++) at[filled[tetrahedra[i]]++] = i - i % 4;
            var seenBy = new int[count];
            for (int k = 0; k < count; k++) seenBy[k] = -1;
            var row = new int[tetrahedra.Length * 3];  // the neighbours, probe-list indices, row after row
            start = new int[count + 1];
            int size = 0;
            for (int a = 0; a < count; a++)
            {
                int first = size;
                for (int i = atStart[a]; i < atStart[a + 1]; i++)
                    for (int c = at[i], end = at[i] + 4; c < end; c++)
                    {
                        int b = tetrahedra[c];
                        if (b == a || seenBy[b] == a) continue;
                        seenBy[b] = a;
                        // Insertion into the row's ascending run (a few tens of neighbours).
                        int j = size++;
                        while (j > first && row[j - 1] > b)
                        {
                            row[j] = row[j - 1];
                            j--;
                        }
                        row[j] = b;
                    }
                start[a + 1] = size;
            }
            target = new int[size];
            for (int e = 0; e < size; e++) target[e] = probes[row[e]];
        }
    }
}
