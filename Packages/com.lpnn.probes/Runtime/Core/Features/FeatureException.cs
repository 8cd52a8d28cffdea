namespace Lpnn.Probes.Core.Features
{
    /// <summary>Features cannot be extracted from these inputs (non-finite lighting, bad raycaster output).</summary>
    public sealed class FeatureException : LpnnException
    {
        public FeatureException(string message) : base(message) { }
    }
}
