using System;

namespace Lpnn.Probes.Core.Features
{
    /// <summary>Per-point feature vectors of one grid (row-major: point n, feature f at n·F + f).</summary>
    public sealed class FeatureSet
    {
        public FeatureSchema Schema { get; }
        public int PointCount { get; }
        public float[] Values { get; }

        /// <summary>The scene scale S (median DC luminance) the lighting features are relative to.</summary>
        public double LightingScale { get; }

        /// <summary>Each point's back-face fraction from the geometry rays (<see cref="ProbeValidity"/>), or null when the
        /// features came from elsewhere (a capture).</summary>
        public float[] BackFaceFractions { get; }

        public FeatureSet(FeatureSchema schema, int pointCount, float[] values, double lightingScale)
            : this(schema, pointCount, values, lightingScale, null) { }

        public FeatureSet(FeatureSchema schema, int pointCount, float[] values, double lightingScale, float[] backFaceFractions)
        {
            Schema = schema ?? throw new ArgumentNullException(nameof(schema));
            if (values == null || values.Length != (long)pointCount * schema.Count)
                throw new ArgumentException("need " + pointCount + " × " + schema.Count + " values", nameof(values));
            PointCount = pointCount;
            Values = values;
            LightingScale = lightingScale;
            if (backFaceFractions != null && backFaceFractions.Length != pointCount)
                throw new ArgumentException("need one back-face fraction per point (" + pointCount + ")", nameof(backFaceFractions));
            BackFaceFractions = backFaceFractions;
        }

        public float this[int point, int feature] => Values[point * Schema.Count + feature];
    }
}
