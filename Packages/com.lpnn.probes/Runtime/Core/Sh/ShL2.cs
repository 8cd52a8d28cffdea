using System;
using System.Collections.Generic;
using System.Numerics;

namespace Lpnn.Probes.Core.Sh
{
    /// <summary>One RGB L2 probe with Unity's <c>SphericalHarmonicsL2</c> layout and conventions: the
    /// object form of <see cref="ShMath"/> for code that handles a few probes at a time.</summary>
    internal sealed class ShL2 : IEquatable<ShL2>
    {
        private readonly float[] _coefficients = new float[ShMath.FloatsPerProbe];

        public ShL2() { }

        public ShL2(float[] source, int offset = 0)
        {
            if (source == null) throw new ArgumentNullException(nameof(source));
            if (offset < 0 || offset + ShMath.FloatsPerProbe > source.Length)
                throw new ArgumentException("need 27 values from offset " + offset + " in an array of " + source.Length, nameof(source));
            Array.Copy(source, offset, _coefficients, 0, ShMath.FloatsPerProbe);
        }

        /// <summary>Coefficient <paramref name="coefficient"/> (0..8) of channel <paramref name="rgb"/> (0..2),
        /// like Unity's indexer.</summary>
        public float this[int rgb, int coefficient]
        {
            get => _coefficients[ShMath.Index(rgb, coefficient)];
            set => _coefficients[ShMath.Index(rgb, coefficient)] = value;
        }

        public void CopyTo(float[] destination, int offset) =>
            Array.Copy(_coefficients, 0, destination, offset, ShMath.FloatsPerProbe);

        public float[] ToArray() => (float[])_coefficients.Clone();

        public Vector3 Evaluate(Vector3 unitDirection) => ShMath.Evaluate(_coefficients, 0, unitDirection);

        public void AddAmbientLight(Vector3 rgb) => ShMath.AddAmbient(_coefficients, 0, rgb);

        public void AddDirectionalLight(Vector3 direction, Vector3 rgb, float intensity) =>
            ShMath.AddDirectional(_coefficients, 0, direction, rgb, intensity);

        /// <summary>Σ weights[k]·probes[k], coefficient-wise in double (probe interpolation).</summary>
        public static ShL2 Blend(IReadOnlyList<ShL2> probes, IReadOnlyList<double> weights)
        {
            if (probes == null) throw new ArgumentNullException(nameof(probes));
            if (weights == null) throw new ArgumentNullException(nameof(weights));
            if (probes.Count != weights.Count)
                throw new ArgumentException(probes.Count + " probes but " + weights.Count + " weights", nameof(weights));
            var sum = new double[ShMath.FloatsPerProbe];
            for (int k = 0; k < probes.Count; k++)
                for (int c = 0; c < ShMath.FloatsPerProbe; c++)
                    sum[c] += weights[k] * probes[k]._coefficients[c];
            var result = new ShL2();
            for (int c = 0; c < ShMath.FloatsPerProbe; c++) result._coefficients[c] = (float)sum[c];
            return result;
        }

        public bool Equals(ShL2 other)
        {
            if (other == null) return false;
            for (int c = 0; c < ShMath.FloatsPerProbe; c++)
                if (!_coefficients[c].Equals(other._coefficients[c])) return false;
            return true;
        }

        public override bool Equals(object obj) => Equals(obj as ShL2);

        public override int GetHashCode()
        {
            int hash = 17;
            foreach (float c in _coefficients) hash = hash * 31 + c.GetHashCode();
            return hash;
        }
    }
}
