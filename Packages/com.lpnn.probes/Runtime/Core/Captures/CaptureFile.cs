using System;
using System.Collections.Generic;
using System.IO;
using System.Text;
using Lpnn.Probes.Core.IO;
using Lpnn.Probes.Core.Json;
using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Core.Captures
{
    /// <summary>Reads, validates, saves and appends capture files (*.lpnncap, Documentation~/file-formats.md):
    /// binary little-endian, self-describing header, CRC-checked, written atomically.</summary>
    public static class CaptureFile
    {
        public const string Extension = ".lpnncap";

        /// <summary>The exact bytes of a capture file; the content is validated first.</summary>
        public static byte[] Encode(Capture capture) => CaptureEncoder.Encode(capture);

        /// <summary>Save: writes (or atomically replaces) one capture file.</summary>
        public static void Save(string path, Capture capture)
        {
            byte[] bytes = CaptureEncoder.Encode(capture);
            AtomicFile.WriteAllBytes(path, bytes);
        }

        /// <summary>Append: writes a new file <c>stem.lpnncap</c> (or <c>stem-2</c>, <c>-3</c>…) into the dataset
        /// folder without ever replacing an existing capture; returns its path.</summary>
        public static string Append(string folder, Capture capture, string stem)
        {
            byte[] bytes = CaptureEncoder.Encode(capture);
            string safe = SafeStem(stem);
            for (int number = 1; number < 1000000; number++)
            {
                string path = Path.Combine(folder, number == 1 ? safe + Extension : safe + "-" + number.ToString(InvariantFormat.Culture) + Extension);
                if (AtomicFile.WriteNew(path, s => s.Write(bytes, 0, bytes.Length))) return path;
            }
            throw new CaptureException(folder + ": no free capture name for '" + safe + "'");
        }

        private static string SafeStem(string stem)
        {
            var builder = new StringBuilder();
            foreach (char c in stem ?? "")
                builder.Append(char.IsLetterOrDigit(c) || c == '-' || c == '_' || c == '.' ? c : '_');
            return builder.Length == 0 ? "capture" : builder.ToString();
        }

        // ------------------------------------------------------------------------------------------ reading

        /// <summary>Reads and fully validates a capture; throws <see cref="CaptureException"/> at the first problem.</summary>
        public static Capture Read(string path)
        {
            byte[] data = ReadBytes(path);
            var capture = CaptureDecoder.Decode(path, data, new ProblemList(false));
            var problems = CaptureContent.Problems(capture, path, true);
            if (problems.Count > 0) throw new CaptureException(problems[0]);
            return capture;
        }

        /// <summary>Every problem of one capture (empty when valid).</summary>
        public static List<string> Validate(string path)
        {
            byte[] data;
            try
            {
                data = ReadBytes(path);
            }
            catch (CaptureException e)
            {
                return new List<string> { e.Message };
            }
            var problems = new ProblemList(true);
            var capture = CaptureDecoder.Decode(path, data, problems);
            if (capture != null) problems.Items.AddRange(CaptureContent.Problems(capture, path, false));
            return problems.Items;
        }

        private static byte[] ReadBytes(string path)
        {
            try
            {
                return File.ReadAllBytes(path);
            }
            catch (Exception e) when (e is IOException || e is UnauthorizedAccessException)
            {
                throw new CaptureException(path + ": cannot read: " + e.Message);
            }
        }

    }
}
