using System;
using System.Numerics;

namespace Lpnn.Probes.Core.Quality
{
    /// <summary>The exact signs of <see cref="RegularInsertion"/>'s determinants, for the rare values its double evaluation
    /// cannot decide (within its rounding bound of 0): every double is an integer times a power of two, so the points'
    /// coordinates and tie heights are scaled to integers (one power of two per kind) and the determinant is computed in
    /// <see cref="BigInteger"/>. Scaling a column or a row by a positive number keeps the sign, so the sign is that of the
    /// determinant of the given doubles, without any rounding: ties are left only where the points really are
    /// coplanar or cospherical (a lattice's axis-aligned planes).</summary>
    internal static class ExactPredicates
    {
        /// <summary>The sign of det[b − a, c − a, d − a] (global point ids into <paramref name="local"/>, x, y, z each).</summary>
        public static int Orient(double[] local, int a, int b, int c, int d)
        {
            var points = new[] { a, b, c, d };
            int exponent = CoordinateExponent(local, points);
            var m = new BigInteger[9];
            for (int r = 0; r < 3; r++)
                for (int k = 0; k < 3; k++)
                    m[3 * r + k] = Scaled(local[3 * points[r + 1] + k], exponent) - Scaled(local[3 * a + k], exponent);
            return Determinant3(m).Sign;
        }

        /// <summary>The sign of the lifted determinant with rows (q − p, |q − p|² + h(q) − h(p)) for q = a, b, c, d.</summary>
        public static int Power(double[] local, double[] height, int a, int b, int c, int d, int p)
        {
            var rows = new[] { a, b, c, d };
            var m = new BigInteger[16];
            LiftedRows(local, height, rows, p, m, new[] { a, b, c, d, p });
            return Determinant4(m).Sign;
        }

        /// <summary>The sign of the lifted determinant with rows (q − a, |q − a|² + h(q) − h(a)) for q = b, c, p and
        /// ((b − a) × (c − a), 0): for p in the plane of (a, b, c), positive when p lies inside their power circle.</summary>
        public static int PowerInPlane(double[] local, double[] height, int a, int b, int c, int p)
        {
            var m = new BigInteger[16];
            LiftedRows(local, height, new[] { b, c, p }, a, m, new[] { a, b, c, p });
            // The normal in the coordinates' squared scale: the row is scaled by a positive number, the sign kept.
            m[12] = m[1] * m[6] - m[2] * m[5];
            m[13] = m[2] * m[4] - m[0] * m[6];
            m[14] = m[0] * m[5] - m[1] * m[4];
            m[15] = BigInteger.Zero;
            return Determinant4(m).Sign;
        }

        /// <summary>Rows (q − o, lifted) of <paramref name="rows"/> about o in integers: coordinates scaled by 2^−e, the lifted
        /// column by 2^−min(2e, the heights' exponent).</summary>
        private static void LiftedRows(double[] local, double[] height, int[] rows, int o, BigInteger[] m, int[] all)
        {
            int coordinate = CoordinateExponent(local, all);
            int heightExponent = int.MaxValue;
            foreach (int q in all) heightExponent = Math.Min(heightExponent, Exponent(height[q]));
            if (heightExponent == int.MaxValue) heightExponent = 2 * coordinate;
            int lifted = Math.Min(2 * coordinate, heightExponent);
            for (int r = 0; r < rows.Length; r++)
            {
                int q = rows[r];
                BigInteger squared = BigInteger.Zero;
                for (int k = 0; k < 3; k++)
                {
                    var delta = Scaled(local[3 * q + k], coordinate) - Scaled(local[3 * o + k], coordinate);
                    m[4 * r + k] = delta;
                    squared += delta * delta;
                }
                m[4 * r + 3] = (squared << (2 * coordinate - lifted)) + Scaled(height[q], lifted) - Scaled(height[o], lifted);
            }
        }

        /// <summary>The smallest exponent of the points' nonzero coordinates (0 when all are 0).</summary>
        private static int CoordinateExponent(double[] local, int[] points)
        {
            int exponent = int.MaxValue;
            foreach (int q in points)
                for (int k = 0; k < 3; k++) exponent = Math.Min(exponent, Exponent(local[3 * q + k]));
            return exponent == int.MaxValue ? 0 : exponent;
        }

        /// <summary>e such that value = m × 2^e with m an odd integer; int.MaxValue for 0.</summary>
        private static int Exponent(double value)
        {
            Decompose(value, out long mantissa, out int exponent);
            if (mantissa == 0) return int.MaxValue;
            while ((mantissa & 1) == 0)
            {
                mantissa >>= 1;
                exponent++;
            }
            return exponent;
        }

        /// <summary>value × 2^−exponent, an integer (exponent at most the value's own, <see cref="Exponent"/>).</summary>
        private static BigInteger Scaled(double value, int exponent)
        {
            Decompose(value, out long mantissa, out int own);
            if (mantissa == 0) return BigInteger.Zero;
            return new BigInteger(mantissa) << (own - exponent);
        }

        /// <summary>value = mantissa × 2^exponent exactly (finite values).</summary>
        private static void Decompose(double value, out long mantissa, out int exponent)
        {
            long bits = BitConverter.DoubleToInt64Bits(value);
            bool negative = bits < 0;
            int biased = (int)((bits >> 52) & 0x7FF);
            long fraction = bits & 0xFFFFFFFFFFFFFL;
            if (biased == 0)
            {
                mantissa = fraction;
                exponent = -1074;
            }
            else
            {
                mantissa = fraction | (1L << 52);
                exponent = biased - 1075;
            }
            if (negative) mantissa = -mantissa;
        }

        private static BigInteger Determinant3(BigInteger[] m) =>
            m[0] * (m[4] * m[8] - m[5] * m[7]) - m[1] * (m[3] * m[8] - m[5] * m[6]) + m[2] * (m[3] * m[7] - m[4] * m[6]);

        private static BigInteger Determinant4(BigInteger[] m)
        {
            var det = BigInteger.Zero;
            var minor = new BigInteger[9];
            for (int col = 0; col < 4; col++)
            {
                for (int r = 1; r < 4; r++)
                    for (int c = 0, k = 0; c < 4; c++)
                        if (c != col) minor[3 * (r - 1) + k++] = m[4 * r + c];
                var term = m[col] * Determinant3(minor);
                det = col % 2 == 0 ? det + term : det - term;
            }
            return det;
        }
    }
}
