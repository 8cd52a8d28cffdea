using System;
using System.Collections.Generic;

namespace Lpnn.Probes.Core.Quality
{
    /// <summary>Each insertion round's tetrahedra for one <see cref="InsertionOrder"/> (quality.md §5.1 step 6), numbered
    /// by <see cref="TetrahedronNumbering"/> (a hash of each tetrahedron's point indices), so that the rounds — which
    /// group points by the tie rule's lowest-index tetrahedron (quality.md §1 "Ties") — depend only on the set of
    /// tetrahedra, not on who built them. Two modes:
    /// - <see cref="Mode.Derived"/> (the default): each round after the first derived from the previous round's
    ///   tetrahedra by inserting the new batch (<see cref="RegularInsertion"/>) instead of a tetrahedralisation (each a
    ///   native call on Unity's main thread, issue 30). A derived round is checked against the tetrahedraliser's own
    ///   answer for the same probes (one more call) until one agrees; a round that disagrees (a tetrahedraliser that
    ///   breaks cospherical ties otherwise, as Unity's native one may, issue 31) takes the tetrahedraliser's answer, and
    ///   the next round derives from it and is checked again (<see cref="Check"/>, <see cref="DerivationCheck"/>'s rule;
    ///   <see cref="DerivationCheck.MaxResyncs"/> disagreements before any agreement tetrahedralise every later round).
    ///   A derivation that fails (an
    ///   undecided sign, a crack in the tetrahedraliser's tetrahedra) tetrahedralises that round, and the next round
    ///   derives from its answer.
    /// - <see cref="Mode.Tetrahedralised"/>: every round tetrahedralised (for comparison; with a tetrahedraliser that
    ///   breaks ties as Python's Qhull does, the two modes give the same rounds).</summary>
    internal sealed class InsertionTetrahedra
    {
        internal enum Mode
        {
            /// <summary>Rounds derived by insertion where possible (the default: the enum's zero, which a thread starts with).</summary>
            Derived,
            /// <summary>The tetrahedraliser every round.</summary>
            Tetrahedralised,
        }

        /// <summary>The mode of orders made on this thread from now on (tests and the Apply bench; per thread, so that a
        /// test cannot leak it into another's run).</summary>
        [ThreadStatic] internal static Mode Setting;

        /// <summary>Tests only: applied to every derived round's tetrahedra before use (null from it: the derivation failed).</summary>
        [ThreadStatic] internal static Func<int[], int[]> AlterDerivedForTests;

        /// <summary>Benches only: told why a round could not be derived (null: nobody listens).</summary>
        [ThreadStatic] internal static Action<string> FallbackListener;

        private readonly ReferenceLighting _reference;
        private readonly ITetrahedralizer _tetrahedralizer;
        private readonly Mode _mode;
        /// <summary>The last round's tetrahedra as an insertion structure; null when the next round must tetrahedralise.</summary>
        private RegularInsertion _mesh;

        /// <summary>Rounds derived, and rounds (or checks) tetrahedralised.</summary>
        internal int Derived { get; private set; }
        internal int Tetrahedralised { get; private set; }
        /// <summary>The comparisons of derived rounds with the tetrahedraliser's answers (<see cref="DerivationCheck"/>).</summary>
        internal DerivationCheck Check { get; } = new DerivationCheck();

        public InsertionTetrahedra(ReferenceLighting reference, ITetrahedralizer tetrahedralizer)
        {
            _reference = reference;
            _tetrahedralizer = tetrahedralizer;
            _mode = Setting;
        }

        /// <summary>The tetrahedra of <paramref name="probes"/> (4 indices into it each), which extend the last round's
        /// probes by the new batch.</summary>
        public int[] Of(int[] probes)
        {
            if (_mode == Mode.Tetrahedralised || !Check.Derives) return Tetrahedralize(probes);
            int[] derived = Derive(probes);
            if (derived != null && Check.Compares)
            {
                int[] fresh = Tetrahedralize(probes);
                double[] points = PlacementError.ProbePoints(_reference, probes);
                if (!Check.Record(TetrahedralMesh.Build(points, derived).HasTheTetrahedraOf(TetrahedralMesh.Build(points, fresh))))
                {
                    FallbackListener?.Invoke("a derived round differs from the tetrahedraliser's (re-synchronised from its answer)");
                    return Synchronised(probes, fresh);
                }
            }
            if (derived != null)
            {
                Derived++;
                return derived;
            }
            return Synchronised(probes, Tetrahedralize(probes));
        }

        /// <summary>The tetrahedraliser's <paramref name="tetrahedra"/> of <paramref name="probes"/>, from which the next
        /// round derives (<see cref="RegularInsertion.Of"/> may refuse them: then the next round tetrahedralises).</summary>
        private int[] Synchronised(int[] probes, int[] tetrahedra)
        {
            _mesh = RegularInsertion.Of(_reference.Local, _reference.TieHeights, probes, tetrahedra, out string refused);
            if (_mesh == null) FallbackListener?.Invoke("the tetrahedraliser's tetrahedra refused: " + refused);
            return tetrahedra;
        }

        /// <summary>The last round's tetrahedra with the new probes inserted, numbered by <see cref="TetrahedronNumbering"/>; null when there is no
        /// usable last round or an insertion fails.</summary>
        private int[] Derive(int[] probes)
        {
            var mesh = _mesh;
            _mesh = null;  // unusable after a failed insertion; restored on success
            if (mesh == null || probes.Length <= mesh.VertexCount) return null;
            for (int k = mesh.VertexCount; k < probes.Length; k++)
                if (!mesh.TryInsert(probes[k]))
                {
                    FallbackListener?.Invoke("an insertion failed: " + mesh.Failure);
                    return null;
                }
            int[] tetrahedra = TetrahedronNumbering.Numbered(mesh.Tetrahedra(), probes);
            if (AlterDerivedForTests != null)
            {
                tetrahedra = AlterDerivedForTests(tetrahedra);
                if (tetrahedra == null) return null;
            }
            _mesh = mesh;
            return tetrahedra;
        }

        private int[] Tetrahedralize(int[] probes)
        {
            Tetrahedralised++;
            return TetrahedronNumbering.Tetrahedralize(_tetrahedralizer, _reference, probes);
        }
    }
}
