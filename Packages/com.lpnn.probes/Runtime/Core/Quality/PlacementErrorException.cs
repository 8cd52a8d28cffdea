namespace Lpnn.Probes.Core.Quality
{
    /// <summary>The placement error cannot be computed from these inputs (too few probes, tetrahedra that name probes
    /// that do not exist, non-finite lighting or positions); the message names the bad value and what to do.</summary>
    public sealed class PlacementErrorException : LpnnException
    {
        public PlacementErrorException(string message) : base(message) { }
    }
}
