namespace Lpnn.Probes.Core.Captures
{
    /// <summary>A capture could not be read or written; the message names the file, the record or line, and the field.</summary>
    public sealed class CaptureException : LpnnException
    {
        public CaptureException(string message) : base(message) { }
    }
}
