using System;
using System.Collections.Generic;
using System.IO;
using System.Text;
using Lpnn.Probes.Core.IO;
using Lpnn.Probes.Core.Json;
using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Core.Captures
{
    /// <summary>Reads the bytes of a capture file back into a <see cref="Capture"/>, checking structure, sizes and CRC.</summary>
    internal static class CaptureDecoder
    {
        public static Capture Decode(string name, byte[] data, ProblemList problems)
        {
            if (data.Length < CaptureFormat.PreambleBytes + CaptureFormat.TrailerBytes)
            {
                problems.Add(name + ": file is " + InvariantFormat.Count(data.Length) + " bytes, too short for a capture (truncated?)");
                return null;
            }
            if (!CaptureFormat.Matches(data, 0, CaptureFormat.Magic))
            {
                problems.Add(name + ": byte 0: not a capture (magic is '" + CaptureFormat.Printable(data, 0, 8) + "', expected 'LPNNCAP\\0')");
                return null;
            }
            uint version = BitConverter.ToUInt32(data, 8), headerLength = BitConverter.ToUInt32(data, 12);
            if (version != CaptureFormat.FormatVersion)
            {
                problems.Add(name + ": byte 8: format version " + version + " is not supported (this reader knows " + CaptureFormat.FormatVersion + ")");
                return null;
            }
            if (CaptureFormat.PreambleBytes + (long)headerLength > data.Length - CaptureFormat.TrailerBytes)
            {
                problems.Add(name + ": byte 12: header length " + InvariantFormat.Count(headerLength) + " runs past the end of the " +
                             InvariantFormat.Count(data.Length) + "-byte file (truncated?)");
                return null;
            }
            JsonValue header;
            try
            {
                header = JsonParser.Parse(new UTF8Encoding(false, true).GetString(data, CaptureFormat.PreambleBytes, (int)headerLength));
            }
            catch (JsonParseException e)
            {
                problems.Add(name + ": header " + e.Message);
                return null;
            }
            catch (ArgumentException)
            {
                problems.Add(name + ": header: not valid UTF-8");
                return null;
            }
            if (header.Kind != JsonKind.Object)
            {
                problems.Add(name + ": header: expected a JSON object");
                return null;
            }
            var fields = HeaderFields.Parse(name, header, problems);
            if (fields == null) return null;
            var arrays = ReadSections(name, data, fields, CaptureFormat.PreambleBytes + (int)headerLength, problems);
            if (arrays == null) return null;

            var extraHeader = JsonValue.NewObject();
            foreach (var member in header.Members)
                if (Array.IndexOf(CaptureFormat.KnownHeaderKeys, member.Key) < 0) extraHeader.Set(member.Key, member.Value);
            return new Capture(arrays.Ids, arrays.Positions, arrays.Sh, arrays.Features, fields.Schema, fields.FeatureNames,
                fields.CellSize, fields.Units, fields.LightingScale, arrays.Labels, fields.LabelSource, fields.Source, arrays.Extra, extraHeader);
        }

        private sealed class SectionArrays
        {
            public int[] Ids;
            public float[] Positions, Sh, Features;
            public byte[] Labels;
            public List<CaptureSection> Extra = new List<CaptureSection>();
        }

        private static SectionArrays ReadSections(string name, byte[] data, HeaderFields fields, int start, ProblemList problems)
        {
            long described = start;
            foreach (var section in fields.Sections) described += section.ByteLength + CaptureFormat.Pad8(section.ByteLength);
            described += CaptureFormat.TrailerBytes;
            if (described != data.Length)
            {
                problems.Add(name + ": file is " + InvariantFormat.Count(data.Length) + " bytes but the header describes " +
                             InvariantFormat.Count(described) + " bytes" + (data.Length < described ? " (truncated?)" : " (trailing bytes?)"));
                return null;
            }
            if (!CaptureFormat.Matches(data, data.Length - 8, CaptureFormat.EndMagic))
            {
                problems.Add(name + ": byte " + InvariantFormat.Count(data.Length - 8) + ": end marker is '" + CaptureFormat.Printable(data, data.Length - 8, 8) +
                             "', expected 'LPNNEND\\0'");
                return null;
            }
            uint stored = BitConverter.ToUInt32(data, data.Length - CaptureFormat.TrailerBytes);
            uint actual = Crc32.Update(0, data, 0, data.Length - CaptureFormat.TrailerBytes);
            if (stored != actual)
            {
                problems.Add(name + ": byte " + InvariantFormat.Count(data.Length - CaptureFormat.TrailerBytes) + ": CRC-32 " + stored.ToString("x8") +
                             " does not match the content (" + actual.ToString("x8") + "): the file is corrupt");
                return null;
            }
            var arrays = new SectionArrays();
            long offset = start;
            foreach (var section in fields.Sections)
            {
                int length = (int)section.ByteLength;
                switch (section.Name)
                {
                    case "ids": arrays.Ids = CaptureFormat.ToInts(data, (int)offset, length); break;
                    case "positions": arrays.Positions = CaptureFormat.ToFloats(data, (int)offset, length); break;
                    case "sh": arrays.Sh = CaptureFormat.ToFloats(data, (int)offset, length); break;
                    case "features": arrays.Features = CaptureFormat.ToFloats(data, (int)offset, length); break;
                    case "labels":
                        arrays.Labels = new byte[length];
                        Buffer.BlockCopy(data, (int)offset, arrays.Labels, 0, length);
                        break;
                    default:
                        var raw = new byte[length];
                        Buffer.BlockCopy(data, (int)offset, raw, 0, length);
                        arrays.Extra.Add(new CaptureSection(section.Name, section.DType, section.Shape, raw));
                        break;
                }
                offset += length + CaptureFormat.Pad8(length);
            }
            return arrays;
        }

    }
}
