using System;
using System.Collections.Generic;
using System.IO;
using System.Text;
using Lpnn.Probes.Core.IO;
using Lpnn.Probes.Core.Json;
using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Core.Captures
{
    /// <summary>Turns a capture into the exact bytes of a capture file (validated first: nothing invalid is written).</summary>
    internal static class CaptureEncoder
    {
        /// <summary>The exact bytes of a capture file; the content is validated first.</summary>
        public static byte[] Encode(Capture capture)
        {
            if (capture == null) throw new ArgumentNullException(nameof(capture));
            if (!BitConverter.IsLittleEndian) throw new PlatformNotSupportedException("capture files are little-endian; this machine is not");
            var problems = CaptureContent.Problems(capture, "<capture being written>", true);
            if (problems.Count > 0) throw new CaptureException(problems[0]);

            var sections = new List<CaptureSection>
            {
                new CaptureSection("ids", "int32", new[] { capture.PointCount, 3 }, CaptureFormat.ToBytes(capture.Ids)),
                new CaptureSection("positions", "float32", new[] { capture.PointCount, 3 }, CaptureFormat.ToBytes(capture.Positions)),
                new CaptureSection("sh", "float32", new[] { capture.PointCount, 27 }, CaptureFormat.ToBytes(capture.Sh)),
                new CaptureSection("features", "float32", new[] { capture.PointCount, capture.FeatureCount }, CaptureFormat.ToBytes(capture.Features)),
            };
            if (capture.Labels != null) sections.Add(new CaptureSection("labels", "uint8", new[] { capture.PointCount }, (byte[])capture.Labels.Clone()));
            sections.AddRange(capture.ExtraSections);

            byte[] header = Encoding.UTF8.GetBytes(JsonWriter.Write(Header(capture, sections)));
            int headerLength = header.Length + CaptureFormat.Pad8(CaptureFormat.PreambleBytes + header.Length);
            using (var stream = new MemoryStream())
            {
                stream.Write(CaptureFormat.Magic, 0, CaptureFormat.Magic.Length);
                CaptureFormat.WriteUInt32(stream, CaptureFormat.FormatVersion);
                CaptureFormat.WriteUInt32(stream, (uint)headerLength);
                stream.Write(header, 0, header.Length);
                for (int pad = header.Length; pad < headerLength; pad++) stream.WriteByte((byte)' ');
                foreach (var section in sections)
                {
                    stream.Write(section.Data, 0, section.Data.Length);
                    for (int pad = 0; pad < CaptureFormat.Pad8(section.Data.Length); pad++) stream.WriteByte(0);
                }
                byte[] body = stream.ToArray();
                uint crc = Crc32.Update(0, body, 0, body.Length);
                CaptureFormat.WriteUInt32(stream, crc);
                CaptureFormat.WriteUInt32(stream, 0);
                stream.Write(CaptureFormat.EndMagic, 0, CaptureFormat.EndMagic.Length);
                return stream.ToArray();
            }
        }

        private static JsonValue Header(Capture capture, List<CaptureSection> sections)
        {
            var header = JsonValue.NewObject();
            header.Set("format", JsonValue.From(CaptureFormat.FormatName));
            header.Set("version", JsonValue.From(CaptureFormat.FormatVersion));
            header.Set("point_count", JsonValue.From(capture.PointCount));
            header.Set("schema", JsonValue.From(capture.Schema));
            var names = JsonValue.NewArray();
            foreach (string name in capture.FeatureNames) names.Add(JsonValue.From(name));
            header.Set("feature_names", names);
            header.Set("cell_size", JsonValue.From(capture.CellSize));
            header.Set("units", JsonValue.From(capture.Units));
            header.Set("lighting_scale", JsonValue.From(capture.LightingScale));
            header.Set("sh_convention", JsonValue.From(Capture.ShConvention));
            header.Set("label_source", JsonValue.From(capture.LabelSource));
            header.Set("source", capture.Source);
            var list = JsonValue.NewArray();
            foreach (var section in sections)
            {
                var entry = JsonValue.NewObject();
                entry.Set("name", JsonValue.From(section.Name));
                entry.Set("dtype", JsonValue.From(section.DType));
                var shape = JsonValue.NewArray();
                foreach (int d in section.Shape) shape.Add(JsonValue.From(d));
                entry.Set("shape", shape);
                list.Add(entry);
            }
            header.Set("sections", list);
            foreach (var member in capture.ExtraHeader.Members)
                if (!header.Has(member.Key)) header.Set(member.Key, member.Value);
            return header;
        }

    }
}
