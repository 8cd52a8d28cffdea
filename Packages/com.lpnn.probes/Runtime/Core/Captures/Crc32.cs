namespace Lpnn.Probes.Core.Captures
{
    /// <summary>CRC-32 (IEEE 802.3, reflected, polynomial 0xEDB88320): the value zlib.crc32 computes, so the
    /// Python tools verify captures written here and vice versa.</summary>
    internal static class Crc32
    {
        private static readonly uint[] Table = BuildTable();

        private static uint[] BuildTable()
        {
            var table = new uint[256];
            for (uint n = 0; n < 256; n++)
            {
                uint c = n;
                for (int k = 0; k < 8; k++) c = (c & 1) != 0 ? 0xEDB88320u ^ (c >> 1) : c >> 1;
                table[n] = c;
            }
            return table;
        }

        /// <summary>Continues a running CRC (start with 0) over bytes[offset .. offset + count).</summary>
        public static uint Update(uint crc, byte[] bytes, int offset, int count)
        {
            uint c = crc ^ 0xFFFFFFFFu;
            for (int i = offset; i < offset + count; i++) c = Table[(c ^ bytes[i]) & 0xFF] ^ (c >> 8);
            return c ^ 0xFFFFFFFFu;
        }
    }
}
