using System;
using System.IO;
using System.Numerics;
using Lpnn.Probes.Core.Features;

/// <summary>The rays of `lpnn place`'s leak rule — Embree over the capture's level — from Python over a pipe
/// (embree_raycaster_server.py, started through a shell script; protocol in its docstring): the Apply benchmark's way of
/// giving the C# leak-aware Apply exactly Python's segment answers, so a difference in probes is the C# core's, not the
/// raycaster's. <see cref="RaysCast"/> counts the rays.</summary>
public sealed class PipeRaycaster : IRaycaster, IDisposable
{
    private readonly System.Diagnostics.Process _process;
    private readonly Stream _in, _out;

    public long RaysCast { get; private set; }

    public PipeRaycaster(string script)
    {
        var info = new System.Diagnostics.ProcessStartInfo("/bin/sh", "\"" + script + "\"")
        {
            UseShellExecute = false, RedirectStandardInput = true, RedirectStandardOutput = true,
        };
        _process = System.Diagnostics.Process.Start(info);
        _in = _process.StandardInput.BaseStream;
        _out = _process.StandardOutput.BaseStream;
    }

    public void Cast(Vector3[] origins, Vector3[] directions, float maxDistance, RayHit[] results)
    {
        int count = origins.Length;
        var request = new byte[8 + 24 * count];
        BitConverter.GetBytes(count).CopyTo(request, 0);
        BitConverter.GetBytes(maxDistance).CopyTo(request, 4);
        var values = new float[6 * count];
        for (int r = 0; r < count; r++)
        {
            values[3 * r] = origins[r].X;
            values[3 * r + 1] = origins[r].Y;
            values[3 * r + 2] = origins[r].Z;
            values[3 * (count + r)] = directions[r].X;
            values[3 * (count + r) + 1] = directions[r].Y;
            values[3 * (count + r) + 2] = directions[r].Z;
        }
        Buffer.BlockCopy(values, 0, request, 8, 24 * count);
        _in.Write(request, 0, request.Length);
        _in.Flush();
        var reply = new float[4 * count];
        var bytes = new byte[16 * count];
        int done = 0;
        while (done < bytes.Length)
        {
            int got = _out.Read(bytes, done, bytes.Length - done);
            if (got <= 0) throw new IOException("the Embree raycaster server stopped");
            done += got;
        }
        Buffer.BlockCopy(bytes, 0, reply, 0, bytes.Length);
        for (int r = 0; r < count; r++)
            results[r] = new RayHit { Distance = reply[r], Normal = new Vector3(reply[count + 3 * r], reply[count + 3 * r + 1], reply[count + 3 * r + 2]) };
        RaysCast += count;
    }

    public void Dispose()
    {
        _in.Close();
        if (!_process.WaitForExit(10000)) _process.Kill();
        _process.Dispose();
    }
}
