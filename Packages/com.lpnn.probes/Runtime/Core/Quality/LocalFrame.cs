using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Core.Quality
{
    /// <summary>Coordinates centred on the evaluation points' bounding box and divided by its largest extent
    /// (Documentation~/quality.md §1, "Scale safety"): every geometric tolerance is then relative, and a volume far from
    /// the origin loses no digits.</summary>
    internal struct LocalFrame
    {
        public readonly Double3 Origin;
        /// <summary>World length of one local unit (the largest extent of the points, &gt; 0).</summary>
        public readonly double Scale;

        private LocalFrame(Double3 origin, double scale)
        {
            Origin = origin;
            Scale = scale;
        }

        /// <summary>The frame of points given as x, y, z triples; <paramref name="scale"/> is 0 when they all coincide.</summary>
        public static LocalFrame Of(double[] xyz)
        {
            double loX = double.PositiveInfinity, loY = double.PositiveInfinity, loZ = double.PositiveInfinity;
            double hiX = double.NegativeInfinity, hiY = double.NegativeInfinity, hiZ = double.NegativeInfinity;
            for (int c = 0; c < xyz.Length; c += 3)
            {
                loX = System.Math.Min(loX, xyz[c]);
                hiX = System.Math.Max(hiX, xyz[c]);
                loY = System.Math.Min(loY, xyz[c + 1]);
                hiY = System.Math.Max(hiY, xyz[c + 1]);
                loZ = System.Math.Min(loZ, xyz[c + 2]);
                hiZ = System.Math.Max(hiZ, xyz[c + 2]);
            }
            double scale = System.Math.Max(hiX - loX, System.Math.Max(hiY - loY, hiZ - loZ));
            return new LocalFrame(new Double3((loX + hiX) / 2, (loY + hiY) / 2, (loZ + hiZ) / 2), scale);
        }

        /// <summary>Converts x, y, z triples in place: (p − origin) / scale.</summary>
        public void ToLocal(double[] xyz)
        {
            for (int c = 0; c < xyz.Length; c += 3)
            {
                xyz[c] = (xyz[c] - Origin.X) / Scale;
                xyz[c + 1] = (xyz[c + 1] - Origin.Y) / Scale;
                xyz[c + 2] = (xyz[c + 2] - Origin.Z) / Scale;
            }
        }
    }
}
