using System;
using System.IO;
using System.Numerics;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Tests.Support;

/// <summary>The rays of `lpnn place`'s leak rule — Embree over the capture's level — from Python over a pipe
/// (embree_raycaster_server.py, started through a shell script; protocol in its docstring): the Apply benchmark's way of
/// giving the C# leak-aware Apply exactly Python's segment answers, so a difference in probes is the C# core's, not the
/// raycaster's. <see cref="RaysCast"/> counts the rays.</summary>
public sealed class PipeRaycaster : IRaycaster, IDisposable
{
    private readonly ScriptPipe _pipe;

    public long RaysCast { get; private set; }

    public PipeRaycaster(string script)
    {
        _pipe = new ScriptPipe(script, "Embree raycaster server");
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
        _pipe.Send(request);
        var reply = new float[4 * count];
        var bytes = _pipe.Read(16 * count);
        Buffer.BlockCopy(bytes, 0, reply, 0, bytes.Length);
        for (int r = 0; r < count; r++)
            results[r] = new RayHit { Distance = reply[r], Normal = new Vector3(reply[count + 3 * r], reply[count + 3 * r + 1], reply[count + 3 * r + 2]) };
        RaysCast += count;
    }

    public void Dispose() => _pipe.Dispose();
}
