using System;
using System.IO;
using System.Text;
using Lpnn.Probes.Core.Captures;

namespace Lpnn.Probes.Core.Scoring
{
    /// <summary>The bytes of a stored <see cref="ScoreRecord"/> (the editor keeps one file per volume in the project's Library
    /// folder: <see cref="ScoreStore"/>). Little-endian: magic "LPNNSCR1", uint32 version 1, the volume's key, the grid
    /// signature, backend and model (each an int32 byte count and UTF-8), float64 cell size, int32 N, int32 ids [N × 3],
    /// float32 scores [N], uint8 1 + uint8 flags [N] (valid) or uint8 0 (unknown), and a CRC-32 of everything before it
    /// (zlib's, <see cref="Crc32"/>). A file is read back only for the key it was written for, so a file-name collision or
    /// a copied Library reads as "no scores", never as another volume's.</summary>
    internal static class ScoreRecordFile
    {
        public const uint Version = 1;
        private static readonly byte[] Magic = Encoding.ASCII.GetBytes("LPNNSCR1");

        public static byte[] Encode(ScoreRecord record, string key)
        {
            if (record == null) throw new ArgumentNullException(nameof(record));
            if (string.IsNullOrEmpty(key)) throw new ArgumentException("a stored record needs its volume's key", nameof(key));
            using (var stream = new MemoryStream())
            {
                using (var writer = new BinaryWriter(stream, Encoding.UTF8, true))
                {
                    writer.Write(Magic);
                    writer.Write(Version);
                    WriteString(writer, key);
                    WriteString(writer, record.GridSignature);
                    WriteString(writer, record.Backend);
                    WriteString(writer, record.Model);
                    writer.Write(record.CellSize);
                    writer.Write(record.Count);
                    foreach (int id in record.Ids) writer.Write(id);
                    foreach (float score in record.Scores) writer.Write(score);
                    var valid = record.Valid;
                    writer.Write((byte)(valid == null ? 0 : 1));
                    if (valid != null) foreach (bool flag in valid) writer.Write((byte)(flag ? 1 : 0));
                }
                byte[] body = stream.ToArray();
                var crc = BitConverter.GetBytes(Crc32.Update(0, body, 0, body.Length));
                if (!BitConverter.IsLittleEndian) Array.Reverse(crc);
                stream.Write(crc, 0, crc.Length);
                return stream.ToArray();
            }
        }

        /// <summary>The record stored in <paramref name="bytes"/> for <paramref name="key"/>, or null when the file was written
        /// for another key. A damaged or foreign file is a <see cref="ScoringException"/> naming what is wrong.</summary>
        public static ScoreRecord Decode(byte[] bytes, string key, string source)
        {
            if (bytes == null) throw new ArgumentNullException(nameof(bytes));
            string where = "the stored scores " + (source ?? "");
            if (bytes.Length < Magic.Length + 8 || !StartsWithMagic(bytes))
                throw new ScoringException(where + " are not an LPNN score file (no LPNNSCR1 magic)");
            uint stored = (uint)(bytes[bytes.Length - 4] | bytes[bytes.Length - 3] << 8 | bytes[bytes.Length - 2] << 16 | bytes[bytes.Length - 1] << 24);
            if (Crc32.Update(0, bytes, 0, bytes.Length - 4) != stored)
                throw new ScoringException(where + " are damaged (checksum mismatch)");
            try
            {
                using (var reader = new BinaryReader(new MemoryStream(bytes, 0, bytes.Length - 4), Encoding.UTF8))
                {
                    reader.ReadBytes(Magic.Length);
                    uint version = reader.ReadUInt32();
                    if (version != Version) throw new ScoringException(where + " have version " + version + "; this package reads version " + Version);
                    string storedKey = ReadString(reader);
                    if (storedKey != key) return null;
                    string signature = ReadString(reader), backend = ReadString(reader), model = ReadString(reader);
                    double cellSize = reader.ReadDouble();
                    int count = reader.ReadInt32();
                    long remaining = reader.BaseStream.Length - reader.BaseStream.Position;
                    if (count < 0 || 16L * count + 1 > remaining)
                        throw new ScoringException(where + " claim " + count + " points in " + remaining + " bytes");
                    var ids = new int[3 * count];
                    for (int i = 0; i < ids.Length; i++) ids[i] = reader.ReadInt32();
                    var scores = new float[count];
                    for (int n = 0; n < count; n++) scores[n] = reader.ReadSingle();
                    bool[] valid = null;
                    byte hasValid = reader.ReadByte();
                    if (hasValid > 1) throw new ScoringException(where + " have a validity marker of " + hasValid);
                    if (hasValid == 1)
                    {
                        valid = new bool[count];
                        for (int n = 0; n < count; n++) valid[n] = reader.ReadByte() != 0;
                    }
                    if (reader.BaseStream.Position != reader.BaseStream.Length)
                        throw new ScoringException(where + " have " + (reader.BaseStream.Length - reader.BaseStream.Position) + " bytes after the record");
                    var record = new ScoreRecord();
                    record.Set(ids, scores, cellSize, backend, model, valid);
                    record.SetGridSignature(signature);
                    return record;
                }
            }
            catch (EndOfStreamException)
            {
                throw new ScoringException(where + " end early (truncated)");
            }
        }

        private static bool StartsWithMagic(byte[] bytes)
        {
            for (int i = 0; i < Magic.Length; i++) if (bytes[i] != Magic[i]) return false;
            return true;
        }

        private static void WriteString(BinaryWriter writer, string text)
        {
            byte[] utf8 = Encoding.UTF8.GetBytes(text ?? "");
            writer.Write(utf8.Length);
            writer.Write(utf8);
        }

        private static string ReadString(BinaryReader reader)
        {
            int length = reader.ReadInt32();
            long remaining = reader.BaseStream.Length - reader.BaseStream.Position;
            if (length < 0 || length > remaining) throw new ScoringException("the stored scores have a string of " + length + " bytes in " + remaining);
            return Encoding.UTF8.GetString(reader.ReadBytes(length));
        }
    }
}
