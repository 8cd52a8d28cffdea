namespace Lpnn.Probes.Core.Selection
{
    /// <summary>A ranking read by its prefixes, computed only as far as it is read (<see cref="Quality.InsertionOrder.Prefix"/>):
    /// returns at least the ranking's first <paramref name="count"/> points, in order (more is allowed).</summary>
    public delegate int[] RankingPrefix(int count);
}
