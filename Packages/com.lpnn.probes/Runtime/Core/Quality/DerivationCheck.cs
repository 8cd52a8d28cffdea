namespace Lpnn.Probes.Core.Quality
{
    /// <summary>Whether tetrahedra derived locally — an insertion round by inserting its batch
    /// (<see cref="InsertionTetrahedra"/>), a refinement trial from its candidates' star refills
    /// (<see cref="BatchedRefinementState"/>) — can stand for the tetrahedraliser's own answer. The derivations break
    /// cospherical ties with Python's tie heights (<see cref="TieBreak"/>); a tetrahedraliser that breaks them otherwise
    /// (Unity's native one may, issue 31), or a degenerate case whose derivation differs (four collinear float32 lattice
    /// probes on a hull face, say), would evaluate a mesh of its own ties in one place and ours in another. So every
    /// derivation is compared with the tetrahedraliser's answer for the same probes (one call) until one agrees; one that
    /// disagrees is replaced by that answer, from which the next derives and is compared again (a re-synchronisation);
    /// after <see cref="MaxResyncs"/> disagreements before any agreement the caller stops deriving. One instance per
    /// insertion order or refinement; Documentation~/quality.md §5.1 step 6 and §5.3.</summary>
    internal sealed class DerivationCheck
    {
        /// <summary>Disagreements before any agreement after which deriving stops: a tetrahedraliser that breaks ties
        /// otherwise disagrees nearly every time, and may agree by chance once few ties are left (a refinement of a small
        /// lattice: 48 disagreements, then one agreement), so a run of disagreements is taken for that, a single one for a
        /// degenerate case.</summary>
        internal const int MaxResyncs = 3;

        /// <summary>Whether a derivation has agreed with the tetrahedraliser (later ones are then not compared).</summary>
        internal bool Agrees { get; private set; }

        /// <summary>Derivations that differed from the tetrahedraliser's answer, which replaced them.</summary>
        internal int Resyncs { get; private set; }

        /// <summary>Whether deriving is still worth trying: fewer than <see cref="MaxResyncs"/> disagreements (none is
        /// counted once one agrees).</summary>
        internal bool Derives => Resyncs < MaxResyncs;

        /// <summary>Whether a derivation must still be compared with the tetrahedraliser's answer.</summary>
        internal bool Compares => !Agrees;

        /// <summary>Records one comparison (only while <see cref="Compares"/>) and returns whether the derivation
        /// agreed; a disagreement counts a re-synchronisation.</summary>
        internal bool Record(bool agreed)
        {
            if (Agrees) throw new System.InvalidOperationException("a derivation was compared after one agreed: nothing is compared once one agrees");
            if (agreed) Agrees = true;
            else Resyncs++;
            return agreed;
        }
    }
}
