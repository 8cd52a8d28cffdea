using System;

namespace Lpnn.Probes.Core.Quality
{
    /// <summary>Mean and 95th percentile of a per-point error over all evaluation points (probes included, at 0).</summary>
    public struct ErrorSummary
    {
        public const double PercentileRank = 95.0;

        public double Mean;
        public double P95;

        /// <summary>The mean (compensated sum, so a million small terms keep their digits) and numpy's default
        /// ("linear") 95th percentile.</summary>
        public static ErrorSummary Of(double[] values)
        {
            double mean = MeanOf(values);  // refuses null and empty values first
            var sorted = (double[])values.Clone();
            Array.Sort(sorted);
            return new ErrorSummary { Mean = mean, P95 = Percentile(sorted, PercentileRank) };
        }

        /// <summary>The <see cref="Mean"/> of <see cref="Of(double[])"/> alone, without the sort its percentile needs (the
        /// tolerance search reads only the mean, many times).</summary>
        public static double MeanOf(double[] values)
        {
            if (values == null) throw new ArgumentNullException(nameof(values));
            if (values.Length == 0) throw new PlacementErrorException("no evaluation points: the error of an empty grid is undefined");
            return CompensatedSum(values) / values.Length;
        }

        /// <summary>The summary over the points where <paramref name="mask"/> is true (e.g. the points in use,
        /// Documentation~/in-use.md), as <see cref="Of(double[])"/> of those values in their order.</summary>
        public static ErrorSummary Of(double[] values, bool[] mask)
        {
            if (values == null) throw new ArgumentNullException(nameof(values));
            if (mask == null) throw new ArgumentNullException(nameof(mask));
            if (mask.Length != values.Length)
                throw new ArgumentException("the mask has " + mask.Length + " flags for " + values.Length + " values; give one per point", nameof(mask));
            int kept = 0;
            foreach (bool flag in mask) if (flag) kept++;
            if (kept == 0) throw new PlacementErrorException("no point is selected by the mask (0 of " + values.Length + "): the error over no points is undefined");
            var selected = new double[kept];
            for (int p = 0, s = 0; p < values.Length; p++) if (mask[p]) selected[s++] = values[p];
            return Of(selected);
        }

        /// <summary>numpy.percentile(values, q) with its default linear interpolation, step for step (numpy 2.x: virtual
        /// index (n − 1)·q/100, then _lerp), so both languages agree to the last bit on equal inputs.</summary>
        public static double Percentile(double[] sorted, double percent)
        {
            if (sorted == null) throw new ArgumentNullException(nameof(sorted));
            int n = sorted.Length;
            if (n == 0) throw new PlacementErrorException("no values: a percentile of nothing is undefined");
            if (!(percent >= 0 && percent <= 100)) throw new ArgumentOutOfRangeException(nameof(percent), percent, "a percentile lies in [0, 100]");
            double q = percent / 100;
            double virtualIndex = (n - 1) * q;
            if (virtualIndex >= n - 1) return sorted[n - 1];
            if (virtualIndex < 0) return sorted[0];
            double previous = Math.Floor(virtualIndex);
            double gamma = virtualIndex - previous;
            double a = sorted[(int)previous], b = sorted[(int)previous + 1];
            double difference = b - a;
            return gamma >= 0.5 ? b - difference * (1 - gamma) : a + difference * gamma;
        }

        /// <summary>Neumaier's compensated summation.</summary>
        private static double CompensatedSum(double[] values)
        {
            double sum = 0, compensation = 0;
            foreach (double v in values)
            {
                double t = sum + v;
                compensation += Math.Abs(sum) >= Math.Abs(v) ? (sum - t) + v : (v - t) + sum;
                sum = t;
            }
            return sum + compensation;
        }
    }
}
