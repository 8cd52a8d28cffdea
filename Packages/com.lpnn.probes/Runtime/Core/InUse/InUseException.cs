namespace Lpnn.Probes.Core.InUse
{
    /// <summary>The in-use rule cannot be applied as asked (a parameter out of range, no seed, no point in use); the
    /// message names the value and the fix.</summary>
    internal sealed class InUseException : LpnnException
    {
        public InUseException(string message) : base(message) { }
    }
}
