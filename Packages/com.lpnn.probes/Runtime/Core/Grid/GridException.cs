namespace Lpnn.Probes.Core.Grid
{
    /// <summary>An evaluation grid cannot be built as asked (bad cell size, no boxes, too many points).</summary>
    public sealed class GridException : LpnnException
    {
        public GridException(string message) : base(message) { }
    }
}
