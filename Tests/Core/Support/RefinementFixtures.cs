using System;
using System.Numerics;
using Lpnn.Probes.Core.Quality;

namespace Lpnn.Probes.Core.Tests.Support
{
    /// <summary>The lit point sets the batched refinement's tests refine (StarRefillTests, FreshCostTests): a lattice whose
    /// unit cells put every cell's corners on one sphere (ties), and a random cloud in general position, both lit by two
    /// blobs.</summary>
    public static class RefinementFixtures
    {
        /// <summary>An nx × ny × nz lattice (unit cells: every cell's corners cospherical) lit by two blobs.</summary>
        public static ReferenceLighting Lattice(int nx, int ny, int nz)
        {
            var positions = QualityFixtures.Positions(QualityFixtures.Box(nx, ny, nz));
            return ReferenceLighting.Create(positions, QualityFixtures.BlobField(positions, new Vector3(1.5f, 1.5f, 1f), new Vector3(3.5f, 2.5f, 2f), 0.9f));
        }

        /// <summary>Random points in a 6 × 5 × 4 box (general position) lit by two blobs.</summary>
        public static ReferenceLighting Cloud(int count, int seed)
        {
            var random = new Random(seed);
            var positions = new Vector3[count];
            for (int n = 0; n < count; n++)
                positions[n] = new Vector3((float)(6 * random.NextDouble()), (float)(5 * random.NextDouble()), (float)(4 * random.NextDouble()));
            return ReferenceLighting.Create(positions, QualityFixtures.BlobField(positions, new Vector3(1.5f, 1.5f, 1f), new Vector3(3.5f, 2.5f, 2f), 0.9f));
        }
    }
}
