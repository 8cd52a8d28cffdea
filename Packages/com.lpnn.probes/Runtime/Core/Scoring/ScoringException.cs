namespace Lpnn.Probes.Core.Scoring
{
    /// <summary>Scoring cannot run as asked (too many points, a backend the machine lacks, a malformed model output).</summary>
    public sealed class ScoringException : LpnnException
    {
        public ScoringException(string message) : base(message) { }
    }
}
