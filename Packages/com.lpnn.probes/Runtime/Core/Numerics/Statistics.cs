using System;
using System.Collections.Generic;

namespace Lpnn.Probes.Core.Numerics
{
    /// <summary>Order statistics shared by the features (scene scale) and the selection (spread weights).</summary>
    public static class Statistics
    {
        /// <summary>The middle value, or the mean of the two middle values for an even count; the input is not changed.</summary>
        public static double Median(IReadOnlyList<double> values)
        {
            if (values == null || values.Count == 0) throw new ArgumentException("the median needs at least one value", nameof(values));
            var sorted = new double[values.Count];
            for (int n = 0; n < sorted.Length; n++) sorted[n] = values[n];
            Array.Sort(sorted);
            int middle = sorted.Length / 2;
            return sorted.Length % 2 == 1 ? sorted[middle] : (sorted[middle - 1] + sorted[middle]) / 2;
        }
    }
}
