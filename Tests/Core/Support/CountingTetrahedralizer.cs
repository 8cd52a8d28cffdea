using System;
using System.Diagnostics;
using System.Linq;
using System.Numerics;
using Lpnn.Probes.Core.Quality;

namespace Lpnn.Probes.Core.Tests.Support
{
    /// <summary>Counts whole-set tetrahedralisations and those of a single star's link (asked by StarRefills) apart.</summary>
    public sealed class CountingTetrahedralizer : ITetrahedralizer
    {
        private readonly ITetrahedralizer _inner;
        private readonly Func<Vector3[], int[], int[]> _links;
        public int Whole, Links;

        /// <param name="links">Replaces a link's answer (null: the inner tetrahedraliser's is kept).</param>
        public CountingTetrahedralizer(ITetrahedralizer inner, Func<Vector3[], int[], int[]> links = null)
        {
            _inner = inner;
            _links = links;
        }

        public int[] Tetrahedralize(Vector3[] positions)
        {
            bool link = new StackTrace().GetFrames().Any(f => f.GetMethod()?.DeclaringType == typeof(StarRefills));
            int[] tets = _inner.Tetrahedralize(positions);
            if (!link)
            {
                Whole++;
                return tets;
            }
            Links++;
            return _links == null ? tets : _links(positions, tets);
        }
    }
}
