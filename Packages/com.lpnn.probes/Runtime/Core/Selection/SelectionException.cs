namespace Lpnn.Probes.Core.Selection
{
    /// <summary>A probe selection cannot be made as asked (bad policy value, a grid with no volume).</summary>
    public sealed class SelectionException : LpnnException
    {
        public SelectionException(string message) : base(message) { }
    }
}
