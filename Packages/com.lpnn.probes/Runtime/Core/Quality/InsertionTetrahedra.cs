using System;
using System.Collections.Generic;
using System.Numerics;

namespace Lpnn.Probes.Core.Quality
{
    /// <summary>Each insertion round's tetrahedra for one <see cref="InsertionOrder"/> (quality.md §5.1 step 6). Today's
    /// rounds (<see cref="Mode.Tetrahedralised"/>, the default) ask the <see cref="ITetrahedralizer"/> for every round's
    /// whole probe set and keep its numbering of the tetrahedra. That numbering is part of the answer: a point on a face,
    /// edge or vertex shared by several tetrahedra belongs to the lowest-index one (quality.md §1 "Ties"), and the round
    /// groups points by that cell, so the same tetrahedra numbered otherwise give other rounds (reversing the
    /// tetrahedraliser's order changes oa_koth1's leak-blind Apply from 180 probes to 197). Hence two opt-in modes, for
    /// measurement until both languages number the tetrahedra one way:
    /// - <see cref="Mode.Canonical"/>: every round tetrahedralised, its tetrahedra numbered canonically (each one's
    ///   corners ascending, then the tetrahedra in ascending order of their corners), so that the numbering depends only
    ///   on the set of tetrahedra;
    /// - <see cref="Mode.Derived"/>: canonical numbering, and each round after the first derived from the previous
    ///   round's tetrahedra by inserting the new batch (<see cref="RegularInsertion"/>) instead of a tetrahedralisation.
    ///   The first derived round is checked against the tetrahedraliser's own answer for the same probes (one more call);
    ///   if the sets differ (a tetrahedraliser that breaks cospherical ties otherwise, as Unity's native one may, issue
    ///   31) the order tetrahedralises every later round. A derivation that fails (an undecided sign, a crack in the
    ///   tetrahedraliser's tetrahedra) tetrahedralises that round, and the next round derives from its answer.
    /// With a tetrahedraliser that breaks ties as Python's Qhull does, the two opt-in modes give the same rounds.</summary>
    internal sealed class InsertionTetrahedra
    {
        internal enum Mode
        {
            /// <summary>Today: the tetrahedraliser every round, its own numbering.</summary>
            Tetrahedralised,
            /// <summary>The tetrahedraliser every round, numbered canonically.</summary>
            Canonical,
            /// <summary>Rounds derived by insertion where possible, numbered canonically.</summary>
            Derived,
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
        /// <summary>Whether the first derived round had the tetrahedraliser's tetrahedra (null: not checked yet).</summary>
        internal bool? Agrees { get; private set; }

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
            if (_mode == Mode.Tetrahedralised) return Tetrahedralize(probes);
            int[] derived = _mode == Mode.Derived && Agrees != false ? Derive(probes) : null;
            if (derived != null && Agrees == null)
            {
                int[] fresh = TetrahedralMesh.Canonical(Tetrahedralize(probes));
                double[] points = PlacementError.ProbePoints(_reference, probes);
                Agrees = TetrahedralMesh.Build(points, derived).HasTheTetrahedraOf(TetrahedralMesh.Build(points, fresh));
                if (Agrees == false)
                {
                    FallbackListener?.Invoke("the first derived round differs from the tetrahedraliser's");
                    _mesh = null;
                    return fresh;
                }
            }
            if (derived != null)
            {
                Derived++;
                return derived;
            }
            int[] tetrahedra = TetrahedralMesh.Canonical(Tetrahedralize(probes));
            if (_mode == Mode.Derived && Agrees != false)
            {
                _mesh = RegularInsertion.Of(_reference.Local, _reference.TieHeights, probes, tetrahedra, out string refused);
                if (_mesh == null) FallbackListener?.Invoke("the tetrahedraliser's tetrahedra refused: " + refused);
            }
            return tetrahedra;
        }

        /// <summary>The last round's tetrahedra with the new probes inserted, numbered canonically; null when there is no
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
            int[] tetrahedra = TetrahedralMesh.Canonical(mesh.Tetrahedra());
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
            var positions = new Vector3[probes.Length];
            for (int k = 0; k < probes.Length; k++) positions[k] = _reference.GetPosition(probes[k]);
            return _tetrahedralizer.Tetrahedralize(positions);
        }
    }
}
