using System;
using System.IO;
using System.Numerics;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Tests.Support;

/// <summary>The rays of `lpnn place`'s leak rule — Embree over the capture's level — from Python over a pipe
/// (embree_raycaster_server.py, started through a shell script; protocol in its docstring): the Apply benchmark's way of
/// giving the C# leak-aware Apply exactly Python's segment answers, so a difference in probes is the C# core's, not the
/// raycaster's. Segments go each to its own end (the server's `first_hit_distances`, as `lpnn place` casts them; distances
/// only, normals left zero). <see cref="RaysCast"/> counts the rays.</summary>
public sealed class PipeRaycaster : IPerRayDistanceRaycaster, IDisposable
{
    /// <summary>The requests' first bytes (embree_raycaster_server.py CAST and OWN_ENDS).</summary>
    private const byte CastRequest = (byte)'C', OwnEndsRequest = (byte)'E';

    private readonly ScriptPipe _pipe;

    public long RaysCast { get; private set; }

    public PipeRaycaster(string script)
    {
        _pipe = new ScriptPipe(script, "Embree raycaster server");
    }

    public void Cast(Vector3[] origins, Vector3[] directions, float maxDistance, RayHit[] results)
    {
        int count = origins.Length;
        _pipe.Send(Request(CastRequest, new[] { maxDistance }, origins, directions));
        var reply = Reply(4 * count);
        for (int r = 0; r < count; r++)
            results[r] = new RayHit { Distance = reply[r], Normal = new Vector3(reply[count + 3 * r], reply[count + 3 * r + 1], reply[count + 3 * r + 2]) };
        RaysCast += count;
    }

    public void Cast(Vector3[] origins, Vector3[] directions, float[] maxDistances, RayHit[] results)
    {
        int count = origins.Length;
        if (maxDistances.Length < count) throw new ArgumentException("fewer maximum distances than origins", nameof(maxDistances));
        var ends = new float[count];
        Array.Copy(maxDistances, ends, count);
        _pipe.Send(Request(OwnEndsRequest, ends, origins, directions));
        var reply = Reply(count);
        for (int r = 0; r < count; r++) results[r] = new RayHit { Distance = reply[r], Normal = Vector3.Zero };
        RaysCast += count;
    }

    /// <summary>kind, int32 R, the floats of <paramref name="distances"/>, R x 3 origins, R x 3 directions.</summary>
    private static byte[] Request(byte kind, float[] distances, Vector3[] origins, Vector3[] directions)
    {
        int count = origins.Length;
        var values = new float[distances.Length + 6 * count];
        distances.CopyTo(values, 0);
        int o = distances.Length, d = o + 3 * count;
        for (int r = 0; r < count; r++)
        {
            values[o + 3 * r] = origins[r].X;
            values[o + 3 * r + 1] = origins[r].Y;
            values[o + 3 * r + 2] = origins[r].Z;
            values[d + 3 * r] = directions[r].X;
            values[d + 3 * r + 1] = directions[r].Y;
            values[d + 3 * r + 2] = directions[r].Z;
        }
        var request = new byte[5 + 4 * values.Length];
        request[0] = kind;
        BitConverter.GetBytes(count).CopyTo(request, 1);
        Buffer.BlockCopy(values, 0, request, 5, 4 * values.Length);
        return request;
    }

    /// <summary>The reply's <paramref name="floats"/> floats.</summary>
    private float[] Reply(int floats)
    {
        var bytes = _pipe.Read(4 * floats);
        var reply = new float[floats];
        Buffer.BlockCopy(bytes, 0, reply, 0, bytes.Length);
        return reply;
    }

    public void Dispose() => _pipe.Dispose();
}
