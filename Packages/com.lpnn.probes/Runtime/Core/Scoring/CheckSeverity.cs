namespace Lpnn.Probes.Core.Scoring
{
    /// <summary>How much a failed model check matters: an error stops scoring, a warning is shown and scoring goes on.</summary>
    public enum CheckSeverity
    {
        Warning = 0,
        Error = 1,
    }
}
