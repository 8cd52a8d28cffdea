using System;

namespace Lpnn.Probes.Core.Numerics
{
    /// <summary>Sorts non-negative 64-bit keys ascending (least-significant-digit radix sort, 16 bits a pass, only the
    /// passes the largest key needs), with an optional payload that moves with each key; stable. Mono's Array.Sort and
    /// List.Sort of long keys call a comparison delegate per comparison (ArraySortHelper), which made sorting the
    /// meshes' faces and edges a tenth of a batched refinement's time (Documentation~/benchmarks.md "The C# core under
    /// Mono"); this takes a few linear passes. Equal keys keep their input order.</summary>
    internal static class KeySort
    {
        private const int DigitBits = 16;
        private const int Digits = 1 << DigitBits;

        /// <summary>Sorts <paramref name="keys"/>[0..<paramref name="count"/>) in place, ascending, and
        /// <paramref name="items"/> (null: none) alongside.</summary>
        /// <exception cref="ArgumentOutOfRangeException">A key is negative (pack keys so that they are not).</exception>
        public static void Sort(long[] keys, int[] items, int count)
        {
            if (keys == null) throw new ArgumentNullException(nameof(keys));
            if (count < 0 || count > keys.Length || (items != null && items.Length < count))
                throw new ArgumentOutOfRangeException(nameof(count), count, "must be within the keys (" + keys.Length + ") and the items given");
            long largest = 0;
            for (int i = 0; i < count; i++)
            {
                if (keys[i] < 0) throw new ArgumentOutOfRangeException(nameof(keys), keys[i], "key " + i + " is negative; pack keys as non-negative numbers");
                if (keys[i] > largest) largest = keys[i];
            }
            if (count < 2) return;
            var bucketStart = new int[Digits];
            long[] sourceKeys = keys, targetKeys = new long[count];
            int[] sourceItems = items, targetItems = items == null ? null : new int[count];
            for (int shift = 0; shift < 64 && (largest >> shift) != 0; shift += DigitBits)
            {
                Array.Clear(bucketStart, 0, Digits);
                for (int i = 0; i < count; i++) bucketStart[(int)((sourceKeys[i] >> shift) & (Digits - 1))]++;
                int sum = 0;
                for (int d = 0; d < Digits; d++)
                {
                    int size = bucketStart[d];
                    bucketStart[d] = sum;
                    sum += size;
                }
                for (int i = 0; i < count; i++)
                {
                    int at = bucketStart[(int)((sourceKeys[i] >> shift) & (Digits - 1))]++;
                    targetKeys[at] = sourceKeys[i];
                    if (sourceItems != null) targetItems[at] = sourceItems[i];
                }
                long[] swapKeys = sourceKeys;
                sourceKeys = targetKeys;
                targetKeys = swapKeys;
                int[] swapItems = sourceItems;
                sourceItems = targetItems;
                targetItems = swapItems;
            }
            if (!ReferenceEquals(sourceKeys, keys))  // an odd number of passes: the sorted run is in the scratch arrays
            {
                Array.Copy(sourceKeys, keys, count);
                if (items != null) Array.Copy(sourceItems, items, count);
            }
        }
    }
}
