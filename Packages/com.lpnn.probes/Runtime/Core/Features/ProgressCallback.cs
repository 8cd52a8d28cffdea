namespace Lpnn.Probes.Core.Features
{
    /// <summary>Reports progress of a long step (<paramref name="done"/> of <paramref name="total"/> units of
    /// <paramref name="stage"/>). Cancellation goes through a CancellationToken, not this callback.</summary>
    public delegate void ProgressCallback(string stage, long done, long total);
}
