using System.Collections.Generic;
using Lpnn.Probes.Core;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Quality;
using UnityEditor;
using NumericsVector3 = System.Numerics.Vector3;

namespace Lpnn.Probes.Editor
{
    /// <summary>Unity's own light-probe tetrahedralisation (UnityEditor.Lightmapping.Tetrahedralize: UnityCsReference
    /// Editor/Mono/GI/Lightmapping.bindings.cs, "the same way the lightmapper" does it), so the estimated error uses the
    /// tetrahedra Unity will interpolate the placed probes with.
    ///
    /// Unity returns its indices into its own position list, from which near-duplicate positions were dropped (so it can
    /// be shorter than the input). They are mapped back to the input by position: exactly equal positions first, the
    /// nearest input otherwise (UNVERIFIED whether Unity ever moves a position; a far match is an error).</summary>
    public sealed class UnityTetrahedralizer : ITetrahedralizer
    {
        /// <summary>A returned position farther than this fraction of the probes' extent from every input is not one of them.</summary>
        private const double MatchTolerance = 1e-4;

        public int[] Tetrahedralize(NumericsVector3[] positions)
        {
            var input = new UnityEngine.Vector3[positions.Length];
            for (int p = 0; p < positions.Length; p++) input[p] = positions[p].ToUnity();
            Lightmapping.Tetrahedralize(input, out int[] indices, out UnityEngine.Vector3[] output);
            if (indices == null || output == null || indices.Length == 0) return new int[0];
            int[] inputOf = MapBack(positions, output);
            var tetrahedra = new int[indices.Length];
            for (int k = 0; k < indices.Length; k++)
            {
                int i = indices[k];
                if ((uint)i >= (uint)output.Length)
                    throw new LpnnException("Unity's tetrahedralisation returned index " + i + " for " + output.Length + " positions; " +
                                            "the placement error cannot be estimated (please report this with the probe count)");
                tetrahedra[k] = inputOf[i];
            }
            return tetrahedra;
        }

        private static int[] MapBack(NumericsVector3[] positions, UnityEngine.Vector3[] output)
        {
            var firstAt = new Dictionary<NumericsVector3, int>(positions.Length);
            for (int p = positions.Length - 1; p >= 0; p--) firstAt[positions[p]] = p;
            double extent = Extent(positions);
            var inputOf = new int[output.Length];
            for (int o = 0; o < output.Length; o++)
            {
                var position = output[o].ToNumerics();
                if (firstAt.TryGetValue(position, out int p))
                {
                    inputOf[o] = p;
                    continue;
                }
                inputOf[o] = Nearest(positions, position, out double distance);
                if (!(distance <= MatchTolerance * extent))
                    throw new LpnnException("Unity's tetrahedralisation returned the position " + InvariantFormat.Vector(position) +
                                            ", which is not one of the probes; the placement error cannot be estimated");
            }
            return inputOf;
        }

        private static int Nearest(NumericsVector3[] positions, NumericsVector3 position, out double distance)
        {
            int best = 0;
            distance = double.PositiveInfinity;
            for (int p = 0; p < positions.Length; p++)
            {
                double d = NumericsVector3.Distance(positions[p], position);
                if (d < distance)
                {
                    distance = d;
                    best = p;
                }
            }
            return best;
        }

        private static double Extent(NumericsVector3[] positions)
        {
            if (positions.Length == 0) return 0;
            NumericsVector3 lo = positions[0], hi = positions[0];
            foreach (var p in positions)
            {
                lo = NumericsVector3.Min(lo, p);
                hi = NumericsVector3.Max(hi, p);
            }
            var size = hi - lo;
            return System.Math.Max(size.X, System.Math.Max(size.Y, size.Z));
        }
    }
}
