using System;

namespace Lpnn.Probes.Core.Grid
{
    /// <summary>A point's stable id: its integer lattice coordinate. World position = cell size × id.
    /// Ordered like the grid: by k (z), then j (y), then i (x).</summary>
    public readonly struct LatticeId : IEquatable<LatticeId>, IComparable<LatticeId>
    {
        /// <summary>Largest |coordinate| allowed, so neighbour offsets can never overflow an int.</summary>
        public const int MaxCoordinate = 1 << 30;

        /// <summary>Largest |coordinate| the grid builder produces: positions (cell size × id) are float32, whose
        /// spacing at cell size × 2^23 is at most one cell, so up to there neighbouring points keep distinct positions.</summary>
        public const int MaxBuiltCoordinate = 1 << 23;

        public readonly int I;
        public readonly int J;
        public readonly int K;

        public LatticeId(int i, int j, int k)
        {
            I = i;
            J = j;
            K = k;
        }

        public int this[int axis]
        {
            get
            {
                switch (axis)
                {
                    case 0: return I;
                    case 1: return J;
                    case 2: return K;
                    default: throw new ArgumentOutOfRangeException(nameof(axis), axis, "axis must be 0, 1 or 2");
                }
            }
        }

        /// <summary>The id <paramref name="offset"/> cells away along <paramref name="axis"/>.</summary>
        public LatticeId Offset(int axis, int offset)
        {
            switch (axis)
            {
                case 0: return new LatticeId(I + offset, J, K);
                case 1: return new LatticeId(I, J + offset, K);
                case 2: return new LatticeId(I, J, K + offset);
                default: throw new ArgumentOutOfRangeException(nameof(axis), axis, "axis must be 0, 1 or 2");
            }
        }

        /// <summary>The id of the half-open cell [p − h/2, p + h/2) holding a world position (floor(p/h + 0.5) per
        /// axis, so each position belongs to exactly one cell); false when that id would be beyond ±2^30.</summary>
        public static bool TryCellOf(Numerics.Double3 position, double cellSize, out LatticeId id)
        {
            double i = Math.Floor(position.X / cellSize + 0.5), j = Math.Floor(position.Y / cellSize + 0.5), k = Math.Floor(position.Z / cellSize + 0.5);
            if (!(Math.Abs(i) <= MaxCoordinate && Math.Abs(j) <= MaxCoordinate && Math.Abs(k) <= MaxCoordinate))
            {
                id = default;
                return false;
            }
            id = new LatticeId((int)i, (int)j, (int)k);
            return true;
        }

        public int CompareTo(LatticeId other)
        {
            if (K != other.K) return K < other.K ? -1 : 1;
            if (J != other.J) return J < other.J ? -1 : 1;
            if (I != other.I) return I < other.I ? -1 : 1;
            return 0;
        }

        public bool Equals(LatticeId other) => I == other.I && J == other.J && K == other.K;
        public override bool Equals(object obj) => obj is LatticeId other && Equals(other);

        public override int GetHashCode()
        {
            unchecked
            {
                // Large odd multipliers spread neighbouring ids across buckets.
                return (I * 73856093) ^ (J * 19349663) ^ (K * 83492791);
            }
        }

        public override string ToString() =>
            I.ToString(Numerics.InvariantFormat.Culture) + "," + J.ToString(Numerics.InvariantFormat.Culture) + "," + K.ToString(Numerics.InvariantFormat.Culture);
    }
}
