using System;
using System.Numerics;
using Lpnn.Probes.Core.Grid;

namespace Lpnn.Probes.Core.Selection
{
    /// <summary>Exact collinearity and coplanarity on integer lattice ids: whether probes can form a tetrahedron
    /// must never depend on floating-point rounding (nor on the distance from the origin).</summary>
    internal static class LatticeGeometry
    {
        /// <summary>Below this coordinate difference every product in the tests fits a long exactly.</summary>
        private const long SmallDifference = 1L << 20;

        /// <summary>Cross product of (b − a) and (c − a), as exact big integers.</summary>
        public static void Cross(LatticeId a, LatticeId b, LatticeId c, out BigInteger x, out BigInteger y, out BigInteger z)
        {
            long ux = (long)b.I - a.I, uy = (long)b.J - a.J, uz = (long)b.K - a.K;
            long vx = (long)c.I - a.I, vy = (long)c.J - a.J, vz = (long)c.K - a.K;
            if (Small(ux, uy, uz) && Small(vx, vy, vz))
            {
                x = uy * vz - uz * vy;
                y = uz * vx - ux * vz;
                z = ux * vy - uy * vx;
                return;
            }
            x = (BigInteger)uy * vz - (BigInteger)uz * vy;
            y = (BigInteger)uz * vx - (BigInteger)ux * vz;
            z = (BigInteger)ux * vy - (BigInteger)uy * vx;
        }

        public static bool Collinear(LatticeId a, LatticeId b, LatticeId c)
        {
            Cross(a, b, c, out var x, out var y, out var z);
            return x.IsZero && y.IsZero && z.IsZero;
        }

        /// <summary>True when d lies in the plane through a, b, c (given a non-zero normal n = (b−a)×(c−a)).</summary>
        public static bool InPlane(LatticeId a, BigInteger nx, BigInteger ny, BigInteger nz, LatticeId d)
        {
            long wx = (long)d.I - a.I, wy = (long)d.J - a.J, wz = (long)d.K - a.K;
            return (nx * wx + ny * wy + nz * wz).IsZero;
        }

        private static bool Small(long x, long y, long z) =>
            Math.Abs(x) < SmallDifference && Math.Abs(y) < SmallDifference && Math.Abs(z) < SmallDifference;
    }
}
