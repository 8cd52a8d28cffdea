namespace Lpnn.Probes.Core.Scoring
{
    /// <summary>A model card is unreadable, or describes a model that cannot score these features or points.</summary>
    public sealed class ModelCardException : LpnnException
    {
        public ModelCardException(string message) : base(message) { }
    }
}
