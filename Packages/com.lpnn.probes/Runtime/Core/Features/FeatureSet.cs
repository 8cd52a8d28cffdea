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

        /// <summary>How many points lie inside a solid collider (<see cref="InsideColliders"/>; their back-face fraction is 1),
        /// 0 when the features came without a collider query.</summary>
        public int InsideColliderCount { get; }

        public FeatureSet(FeatureSchema schema, int pointCount, float[] values, double lightingScale)
            : this(schema, pointCount, values, lightingScale, null) { }

        public FeatureSet(FeatureSchema schema, int pointCount, float[] values, double lightingScale, float[] backFaceFractions)
            : this(schema, pointCount, values, lightingScale, backFaceFractions, 0) { }

        internal FeatureSet(FeatureSchema schema, int pointCount, float[] values, double lightingScale, float[] backFaceFractions, int insideColliderCount)
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
            if (insideColliderCount < 0 || insideColliderCount > pointCount || (insideColliderCount > 0 && backFaceFractions == null))
                throw new ArgumentException("the count of points inside colliders (" + insideColliderCount + ") needs back-face fractions and at most " + pointCount, nameof(insideColliderCount));
            InsideColliderCount = insideColliderCount;
        }

        public float this[int point, int feature] => Values[point * Schema.Count + feature];
    }
}
