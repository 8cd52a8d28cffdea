using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Core.Quality
{
    /// <summary>Checks a probe set given as evaluation point indices: probes are grid points, so an index out of range
    /// or listed twice would pair a probe with the wrong lighting (LumiProbes bug B2).</summary>
    internal static class ProbeIndices
    {
        /// <summary>Unity interpolates inside tetrahedra: fewer probes than this cannot make one.</summary>
        public const int Minimum = 4;

        public static void Check(int[] probes, int pointCount)
        {
            if (probes == null) throw new System.ArgumentNullException(nameof(probes));
            if (probes.Length < Minimum)
                throw new PlacementErrorException(probes.Length + " probe(s) cannot be tetrahedralised: Unity needs at least 4 probes that are not all in one plane");
            var seen = new bool[pointCount];
            foreach (int p in probes)
            {
                if ((uint)p >= (uint)pointCount)
                    throw new PlacementErrorException("probe index " + p + " is outside the " + InvariantFormat.Count(pointCount) + " evaluation points");
                if (seen[p]) throw new PlacementErrorException("probe index " + p + " is listed more than once: remove duplicates");
                seen[p] = true;
            }
        }
    }
}
