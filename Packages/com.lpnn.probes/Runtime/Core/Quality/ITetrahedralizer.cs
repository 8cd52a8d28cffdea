using System.Numerics;

namespace Lpnn.Probes.Core.Quality
{
    /// <summary>Builds the tetrahedra a probe set is interpolated with. In the editor this is Unity's own
    /// (the editor's Lightmapping.Tetrahedralize), so the estimated error uses the tetrahedra Unity will render with;
    /// the core never depends on it.</summary>
    public interface ITetrahedralizer
    {
        /// <summary>Tetrahedra as index quadruples into <paramref name="positions"/> (4 ints per tetrahedron, any
        /// orientation). Positions the tetrahedralisation dropped (near-duplicates) simply appear in no tetrahedron.</summary>
        int[] Tetrahedralize(Vector3[] positions);
    }
}
