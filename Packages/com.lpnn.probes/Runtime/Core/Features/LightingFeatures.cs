using System;
using System.Threading;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Sh;

namespace Lpnn.Probes.Core.Features
{
    /// <summary>Features 0–14 of lpnn.features.v1: what the lighting is at a point and how fast it changes to
    /// its grid neighbours (Documentation~/features.md). Neighbours are read through grid ids only, so the light
    /// sampler is needed once per evaluation point and nowhere else.</summary>
    internal static class LightingFeatures
    {
        public const int Count = 15;
        public const double Epsilon = 1e-3;
        private const int Directions = 14;
        private const int ValuesPerPoint = Directions * 3;
        private static readonly int[] Scales = { 1, 2, 4 };

        public static void Compute(EvaluationGrid grid, float[] sh, double scale, float[] output, int stride,
            ProgressCallback progress, CancellationToken cancel)
        {
            int count = grid.Count;
            float[] irradiance = EvaluateAll(sh, count, progress, cancel);
            double floorTerm = ValuesPerPoint * Epsilon * scale;
            var features = new double[Count];
            for (int n = 0; n < count; n++)
            {
                if ((n & 4095) == 0)
                {
                    progress?.Invoke("lighting features", n, count);
                    cancel.ThrowIfCancellationRequested();
                }
                PointFeatures(sh, irradiance, n, scale, features);
                NeighbourFeatures(grid, irradiance, n, floorTerm, features);
                int o = n * stride;
                for (int f = 0; f < Count; f++) output[o + f] = (float)features[f];
            }
            progress?.Invoke("lighting features", count, count);
            cancel.ThrowIfCancellationRequested();
        }

        /// <summary>E(p, d) for every point and every D14 direction (RGB), cached once: each point is read by up
        /// to 18 neighbours.</summary>
        private static float[] EvaluateAll(float[] sh, int count, ProgressCallback progress, CancellationToken cancel)
        {
            var values = new float[(long)count * ValuesPerPoint];
            for (int n = 0; n < count; n++)
            {
                if ((n & 8191) == 0)
                {
                    progress?.Invoke("evaluating lighting", n, count);
                    cancel.ThrowIfCancellationRequested();
                }
                int o = n * ShMath.FloatsPerProbe;
                for (int d = 0; d < Directions; d++)
                {
                    ShMath.Evaluate(sh, o, DirectionSets.D14[d, 0], DirectionSets.D14[d, 1], DirectionSets.D14[d, 2],
                        out double r, out double g, out double b);
                    long v = (long)n * ValuesPerPoint + 3 * d;
                    values[v] = (float)r;
                    values[v + 1] = (float)g;
                    values[v + 2] = (float)b;
                }
            }
            return values;
        }

        /// <summary>Features 0–7: level, chroma and directional structure at the point itself.</summary>
        private static void PointFeatures(float[] sh, float[] irradiance, int n, double scale, double[] features)
        {
            int o = n * ShMath.FloatsPerProbe;
            const int G = ShMath.CoefficientsPerChannel, B = 2 * ShMath.CoefficientsPerChannel;
            double r0 = sh[o], g0 = sh[o + G], b0 = sh[o + B];
            double y0 = ColorSpaces.Luminance(r0, g0, b0);
            double lit = Math.Max(y0, 0);
            double floor = lit + Epsilon * scale;
            features[0] = Math.Log(lit / scale + Epsilon);
            features[1] = (r0 - b0) / 2 / floor;
            features[2] = (-r0 / 4 + g0 / 2 - b0 / 4) / floor;
            double l1Sum = 0;
            for (int m = 1; m <= 3; m++)
            {
                double l = ColorSpaces.Luminance(sh[o + m], sh[o + G + m], sh[o + B + m]);
                l1Sum += l * l;
            }
            features[3] = Math.Sqrt(l1Sum) / floor;

            // Population variances over D14, two-pass so nearly uniform light does not cancel catastrophically.
            long v0 = (long)n * ValuesPerPoint;
            double meanY = 0, meanR = 0, meanG = 0, meanB = 0;
            for (int d = 0; d < Directions; d++)
            {
                double r = irradiance[v0 + 3 * d], g = irradiance[v0 + 3 * d + 1], b = irradiance[v0 + 3 * d + 2];
                meanY += ColorSpaces.Luminance(r, g, b);
                meanR += r;
                meanG += g;
                meanB += b;
            }
            meanY /= Directions;
            meanR /= Directions;
            meanG /= Directions;
            meanB /= Directions;
            double varY = 0, varR = 0, varG = 0, varB = 0;
            for (int d = 0; d < Directions; d++)
            {
                double r = irradiance[v0 + 3 * d], g = irradiance[v0 + 3 * d + 1], b = irradiance[v0 + 3 * d + 2];
                double dy = ColorSpaces.Luminance(r, g, b) - meanY;
                varY += dy * dy;
                varR += (r - meanR) * (r - meanR);
                varG += (g - meanG) * (g - meanG);
                varB += (b - meanB) * (b - meanB);
            }
            double floorSquared = floor * floor * Directions;
            features[4] = varY / floorSquared;
            features[5] = varR / floorSquared;
            features[6] = varG / floorSquared;
            features[7] = varB / floorSquared;
        }

        /// <summary>Features 8–14: missing face neighbours, and lighting change / interpolation error at 1, 2 and
        /// 4 cells.</summary>
        private static void NeighbourFeatures(EvaluationGrid grid, float[] irradiance, int n, double floorTerm, double[] features)
        {
            int missing = 0;
            for (int axis = 0; axis < 3; axis++)
            {
                if (grid.Neighbour(n, axis, 1) < 0) missing++;
                if (grid.Neighbour(n, axis, -1) < 0) missing++;
            }
            features[8] = missing / 6.0;
            for (int s = 0; s < Scales.Length; s++)
            {
                int k = Scales[s];
                double change = 0, curvature = 0;
                for (int axis = 0; axis < 3; axis++)
                {
                    int plus = grid.Neighbour(n, axis, k), minus = grid.Neighbour(n, axis, -k);
                    if (plus >= 0) change = Math.Max(change, Relative(irradiance, n, plus, -1, floorTerm));
                    if (minus >= 0) change = Math.Max(change, Relative(irradiance, n, minus, -1, floorTerm));
                    if (plus >= 0 && minus >= 0)
                        curvature = Math.Max(curvature, Relative(irradiance, n, plus, minus, floorTerm));
                }
                features[9 + s] = change;
                features[12 + s] = curvature;
            }
        }

        /// <summary>rel(E(p), T) = Σ|E(p) − T| / (Σ(|E(p)| + |T|) + 42·ε·S) over the 42 irradiance values, where
        /// T = E(other) — or, when <paramref name="otherMinus"/> ≥ 0, the midpoint (E(other) + E(otherMinus))/2: the
        /// error of interpolating p linearly from its two neighbours, i.e. what dropping the probe at p costs when
        /// probes k cells away remain.</summary>
        private static double Relative(float[] irradiance, int p, int other, int otherMinus, double floorTerm)
        {
            long op = (long)p * ValuesPerPoint, oa = (long)other * ValuesPerPoint;
            long ob = otherMinus >= 0 ? (long)otherMinus * ValuesPerPoint : oa;
            double difference = 0, magnitude = 0;
            for (int v = 0; v < ValuesPerPoint; v++)
            {
                double x = irradiance[op + v];
                double y = ((double)irradiance[oa + v] + irradiance[ob + v]) / 2;
                difference += Math.Abs(x - y);
                magnitude += Math.Abs(x) + Math.Abs(y);
            }
            return difference / (magnitude + floorTerm);
        }
    }
}
