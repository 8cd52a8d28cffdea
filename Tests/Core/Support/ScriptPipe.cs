using System;
using System.IO;

namespace Lpnn.Probes.Core.Tests.Support
{
    /// <summary>A helper process started through a shell script that answers binary requests on stdin with binary replies
    /// on stdout: how the tests and benchmarks get Python's answers (its tetrahedralisation, Embree's rays) for the C#
    /// core (rehearsal_tetrahedralizer.py, embree_raycaster_server.py; their protocols in their docstrings).</summary>
    public sealed class ScriptPipe : IDisposable
    {
        private readonly System.Diagnostics.Process _process;
        private readonly Stream _in, _out;
        private readonly string _what;

        /// <param name="script">A shell script that execs the helper.</param>
        /// <param name="what">The helper's name in the error raised when it stops answering.</param>
        public ScriptPipe(string script, string what)
        {
            var info = new System.Diagnostics.ProcessStartInfo("/bin/sh", "\"" + script + "\"")
            {
                UseShellExecute = false, RedirectStandardInput = true, RedirectStandardOutput = true,
            };
            _process = System.Diagnostics.Process.Start(info);
            _in = _process.StandardInput.BaseStream;
            _out = _process.StandardOutput.BaseStream;
            _what = what;
        }

        /// <summary>Sends a whole request.</summary>
        public void Send(byte[] request)
        {
            _in.Write(request, 0, request.Length);
            _in.Flush();
        }

        /// <summary>Exactly <paramref name="size"/> bytes of the reply; IOException when the helper stops first.</summary>
        public byte[] Read(int size)
        {
            var data = new byte[size];
            int done = 0;
            while (done < size)
            {
                int got = _out.Read(data, done, size - done);
                if (got <= 0) throw new IOException("the " + _what + " stopped");
                done += got;
            }
            return data;
        }

        public void Dispose()
        {
            _in.Close();
            if (!_process.WaitForExit(10000)) _process.Kill();
            _process.Dispose();
        }
    }
}
