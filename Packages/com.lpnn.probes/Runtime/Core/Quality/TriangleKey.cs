using System;

namespace Lpnn.Probes.Core.Quality
{
    /// <summary>A triangle by its three corner indices, equal whatever their order: the key under which the batched
    /// refinement's refills find the faces they share with each other and with the tetrahedra kept around them
    /// (<see cref="StarRefills"/>, <see cref="TetrahedraAfterRemoval"/>), and under which a mesh pairs its tetrahedra's faces
    /// (<see cref="TetrahedralMesh"/>).</summary>
    internal readonly struct TriangleKey : IEquatable<TriangleKey>
    {
        public readonly int A, B, C;  // ascending

        public TriangleKey(int x, int y, int z)
        {
            A = Math.Min(x, Math.Min(y, z));
            C = Math.Max(x, Math.Max(y, z));
            B = x + y + z - A - C;
        }

        public bool Equals(TriangleKey other) => A == other.A && B == other.B && C == other.C;
        public override bool Equals(object obj) => obj is TriangleKey other && Equals(other);
        public override int GetHashCode() => unchecked((A * 73856093) ^ (B * 19349663) ^ (C * 83492791));
    }
}
