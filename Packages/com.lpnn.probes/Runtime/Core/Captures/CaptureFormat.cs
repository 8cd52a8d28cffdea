using System;
using System.Collections.Generic;
using System.IO;
using System.Text;
using Lpnn.Probes.Core.IO;
using Lpnn.Probes.Core.Json;
using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Core.Captures
{
    /// <summary>Fixed layout facts of the capture format and the byte helpers every part of it shares.</summary>
    internal static class CaptureFormat
    {
        public const string FormatName = "lpnn.capture";
        public const int FormatVersion = 1;
        public const int PreambleBytes = 16;
        public const int TrailerBytes = 16;
        public static readonly byte[] Magic = Encoding.ASCII.GetBytes("LPNNCAP\0");
        public static readonly byte[] EndMagic = Encoding.ASCII.GetBytes("LPNNEND\0");

        public static readonly string[] KnownHeaderKeys =
        {
            "format", "version", "point_count", "schema", "feature_names", "cell_size", "units",
            "lighting_scale", "sh_convention", "label_source", "source", "sections",
        };

        public static int Pad8(long length) => (int)((8 - length % 8) % 8);

        public static bool Matches(byte[] data, int offset, byte[] expected)
        {
            for (int i = 0; i < expected.Length; i++)
                if (data[offset + i] != expected[i]) return false;
            return true;
        }

        public static string Printable(byte[] data, int offset, int count)
        {
            var builder = new StringBuilder();
            for (int i = offset; i < offset + count && i < data.Length; i++)
            {
                byte b = data[i];
                builder.Append(b >= 0x20 && b < 0x7F ? ((char)b).ToString() : "\\x" + b.ToString("x2"));
            }
            return builder.ToString();
        }

        public static void WriteUInt32(Stream stream, uint value)
        {
            var bytes = BitConverter.GetBytes(value);
            stream.Write(bytes, 0, 4);
        }

        public static byte[] ToBytes(Array values)
        {
            var bytes = new byte[Buffer.ByteLength(values)];
            Buffer.BlockCopy(values, 0, bytes, 0, bytes.Length);
            return bytes;
        }

        public static int[] ToInts(byte[] data, int offset, int length)
        {
            var values = new int[length / 4];
            Buffer.BlockCopy(data, offset, values, 0, length);
            return values;
        }

        public static float[] ToFloats(byte[] data, int offset, int length)
        {
            var values = new float[length / 4];
            Buffer.BlockCopy(data, offset, values, 0, length);
            return values;
        }
    }
}
