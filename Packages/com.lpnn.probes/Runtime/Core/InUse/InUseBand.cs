namespace Lpnn.Probes.Core.InUse
{
    /// <summary>The band of Documentation~/in-use.md "Definitions" 1, per grid point: in band, and the floor height f(p)
    /// (NaN where not in band).</summary>
    internal sealed class InUseBand
    {
        public bool[] InBand { get; }
        public double[] FloorHeights { get; }

        public InUseBand(bool[] inBand, double[] floorHeights)
        {
            InBand = inBand;
            FloorHeights = floorHeights;
        }

        public int Count
        {
            get
            {
                int count = 0;
                foreach (bool inBand in InBand) if (inBand) count++;
                return count;
            }
        }
    }
}
