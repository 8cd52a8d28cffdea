using System;
using System.Numerics;

namespace Lpnn.Probes.Core.Numerics
{
    /// <summary>A double-precision 3-vector: grid and geometry math stay exact far from the origin,
    /// where float32 positions would already have lost the sub-cell digits.</summary>
    public readonly struct Double3 : IEquatable<Double3>
    {
        public readonly double X;
        public readonly double Y;
        public readonly double Z;

        public Double3(double x, double y, double z)
        {
            X = x;
            Y = y;
            Z = z;
        }

        public static readonly Double3 Zero = new Double3(0, 0, 0);

        public double this[int axis]
        {
            get
            {
                switch (axis)
                {
                    case 0: return X;
                    case 1: return Y;
                    case 2: return Z;
                    default: throw new ArgumentOutOfRangeException(nameof(axis), axis, "axis must be 0, 1 or 2");
                }
            }
        }

        public static Double3 operator +(Double3 a, Double3 b) => new Double3(a.X + b.X, a.Y + b.Y, a.Z + b.Z);
        public static Double3 operator -(Double3 a, Double3 b) => new Double3(a.X - b.X, a.Y - b.Y, a.Z - b.Z);
        public static Double3 operator -(Double3 a) => new Double3(-a.X, -a.Y, -a.Z);
        public static Double3 operator *(Double3 a, double s) => new Double3(a.X * s, a.Y * s, a.Z * s);
        public static Double3 operator *(double s, Double3 a) => a * s;

        public static double Dot(Double3 a, Double3 b) => a.X * b.X + a.Y * b.Y + a.Z * b.Z;

        public static Double3 Cross(Double3 a, Double3 b) =>
            new Double3(a.Y * b.Z - a.Z * b.Y, a.Z * b.X - a.X * b.Z, a.X * b.Y - a.Y * b.X);

        public double LengthSquared => X * X + Y * Y + Z * Z;
        public double Length => Math.Sqrt(LengthSquared);

        public bool IsFinite => IsFiniteNumber(X) && IsFiniteNumber(Y) && IsFiniteNumber(Z);

        public static bool IsFiniteNumber(double value) => !double.IsNaN(value) && !double.IsInfinity(value);

        public static Double3 FromVector3(Vector3 v) => new Double3(v.X, v.Y, v.Z);

        /// <summary>Point <paramref name="i"/> of a flat array of x, y, z triples (the core's local positions).</summary>
        internal static Double3 FromTriples(double[] xyz, int i) => new Double3(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);

        public bool Equals(Double3 other) => X.Equals(other.X) && Y.Equals(other.Y) && Z.Equals(other.Z);
        public override bool Equals(object obj) => obj is Double3 other && Equals(other);
        public override int GetHashCode() => X.GetHashCode() * 397 ^ Y.GetHashCode() * 31 ^ Z.GetHashCode();

        public override string ToString() =>
            "(" + InvariantFormat.Number(X) + ", " + InvariantFormat.Number(Y) + ", " + InvariantFormat.Number(Z) + ")";
    }
}
