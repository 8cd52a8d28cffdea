using System;
using System.IO;

namespace Lpnn.Probes.Core.IO
{
    /// <summary>Writes files so that nothing is lost on failure: a temporary file beside the target is
    /// written and flushed, then renamed. Either the old file (or none) or the complete new one remains.</summary>
    internal static class AtomicFile
    {
        /// <summary>Writes (or atomically replaces) <paramref name="path"/>.</summary>
        public static void Write(string path, Action<Stream> writer)
        {
            string full = Path.GetFullPath(path);
            string temporary = WriteTemporary(full, writer);
            try
            {
                if (File.Exists(full))
                    File.Replace(temporary, full, null);
                else
                    File.Move(temporary, full);
            }
            finally
            {
                if (File.Exists(temporary)) File.Delete(temporary);
            }
        }

        /// <summary>Writes <paramref name="path"/> only if it does not exist; returns false (writing
        /// nothing) when the name is taken. Used by dataset append, which must never alter a file.</summary>
        public static bool WriteNew(string path, Action<Stream> writer)
        {
            string full = Path.GetFullPath(path);
            if (File.Exists(full)) return false;
            string temporary = WriteTemporary(full, writer);
            try
            {
                // File.Move refuses an existing destination, so a name taken meanwhile is not overwritten.
                File.Move(temporary, full);
                return true;
            }
            catch (IOException) when (File.Exists(full))
            {
                return false;
            }
            finally
            {
                if (File.Exists(temporary)) File.Delete(temporary);
            }
        }

        public static void WriteAllBytes(string path, byte[] bytes) => Write(path, s => s.Write(bytes, 0, bytes.Length));

        private static string WriteTemporary(string fullPath, Action<Stream> writer)
        {
            string directory = Path.GetDirectoryName(fullPath);
            if (!string.IsNullOrEmpty(directory)) Directory.CreateDirectory(directory);
            string temporary = Path.Combine(directory ?? ".",
                "." + Path.GetFileName(fullPath) + "." + Guid.NewGuid().ToString("N").Substring(0, 12) + ".tmp");
            try
            {
                using (var stream = new FileStream(temporary, FileMode.CreateNew, FileAccess.Write, FileShare.None))
                {
                    writer(stream);
                    stream.Flush(true);
                }
                return temporary;
            }
            catch
            {
                if (File.Exists(temporary)) File.Delete(temporary);
                throw;
            }
        }
    }
}
