using System;
using System.Collections.Generic;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Json;
using Lpnn.Probes.Core.Sh;

namespace Lpnn.Probes.Core.Captures
{
    /// <summary>An optional, extra per-point section of a capture, carried along as raw little-endian bytes.</summary>
    public sealed class CaptureSection
    {
        public string Name { get; }
        /// <summary>"int32", "float32" or "uint8".</summary>
        public string DType { get; }
        public int[] Shape { get; }
        public byte[] Data { get; }

        public CaptureSection(string name, string dtype, int[] shape, byte[] data)
        {
            Name = name;
            DType = dtype;
            Shape = shape;
            Data = data;
        }
    }

    /// <summary>One evaluation grid of one scene with its lighting, features, optional labels and provenance:
    /// what "Save" and "Append" export for retraining (Documentation~/file-formats.md).</summary>
    public sealed class Capture
    {
        public const string ShConvention = "unity.SphericalHarmonicsL2";

        public int PointCount { get; }
        /// <summary>Lattice ids, i,j,k per point, in grid order.</summary>
        public int[] Ids { get; }
        public float[] Positions { get; }
        public float[] Sh { get; }
        public float[] Features { get; }
        public string Schema { get; }
        public IReadOnlyList<string> FeatureNames { get; }
        public double CellSize { get; }
        public string Units { get; }
        public double LightingScale { get; }
        /// <summary>0/1 per point, or null when the capture has no labels.</summary>
        public byte[] Labels { get; }
        public string LabelSource { get; }
        /// <summary>Free-form provenance (a JSON object).</summary>
        public JsonValue Source { get; }
        public IReadOnlyList<CaptureSection> ExtraSections { get; }
        /// <summary>Header keys this version does not know, kept so rewriting a capture loses nothing.</summary>
        public JsonValue ExtraHeader { get; }

        public int FeatureCount => FeatureNames.Count;

        public Capture(int[] ids, float[] positions, float[] sh, float[] features, string schema, IReadOnlyList<string> featureNames,
            double cellSize, string units, double lightingScale, byte[] labels = null, string labelSource = null,
            JsonValue source = null, IReadOnlyList<CaptureSection> extraSections = null, JsonValue extraHeader = null)
        {
            Ids = ids ?? throw new ArgumentNullException(nameof(ids));
            PointCount = ids.Length / 3;
            Positions = positions ?? throw new ArgumentNullException(nameof(positions));
            Sh = sh ?? throw new ArgumentNullException(nameof(sh));
            Features = features ?? throw new ArgumentNullException(nameof(features));
            Schema = schema ?? throw new ArgumentNullException(nameof(schema));
            FeatureNames = featureNames ?? throw new ArgumentNullException(nameof(featureNames));
            CellSize = cellSize;
            Units = units ?? "m";
            LightingScale = lightingScale;
            Labels = labels;
            LabelSource = labelSource;
            Source = source ?? JsonValue.NewObject();
            ExtraSections = extraSections ?? new CaptureSection[0];
            ExtraHeader = extraHeader ?? JsonValue.NewObject();
        }

        /// <summary>A capture of a grid with its SH and features, e.g. for export from the editor.</summary>
        public static Capture FromGrid(EvaluationGrid grid, float[] sh, FeatureSet features, JsonValue source = null,
            byte[] labels = null, string labelSource = null, string units = "m")
        {
            if (grid == null) throw new ArgumentNullException(nameof(grid));
            if (features == null) throw new ArgumentNullException(nameof(features));
            if (sh == null || sh.Length != (long)grid.Count * ShMath.FloatsPerProbe)
                throw new ArgumentException("need 27 SH floats per evaluation point", nameof(sh));
            if (features.PointCount != grid.Count)
                throw new ArgumentException("features are for " + features.PointCount + " points, the grid has " + grid.Count, nameof(features));
            // The rays' back-face fractions travel as an optional section, so `lpnn place` never picks a point inside
            // geometry (Documentation~/file-formats.md, features.md "Probe validity").
            var extra = features.BackFaceFractions == null ? null : new[]
            {
                new CaptureSection(ProbeValidity.CaptureSection, "float32", new[] { grid.Count }, CaptureFormat.ToBytes(features.BackFaceFractions)),
            };
            return new Capture(grid.CopyIds(), grid.CopyPositions(), (float[])sh.Clone(), (float[])features.Values.Clone(),
                features.Schema.Id, features.Schema.Names, grid.CellSize, units, features.LightingScale, labels, labelSource, source, extra);
        }

        /// <summary>The same capture with labels (e.g. from ground-truth probes).</summary>
        public Capture WithLabels(byte[] labels, string labelSource) =>
            new Capture(Ids, Positions, Sh, Features, Schema, FeatureNames, CellSize, Units, LightingScale, labels, labelSource,
                Source, ExtraSections, ExtraHeader);

        /// <summary>The same capture with one more per-point section (e.g. "in_use", Documentation~/in-use.md).</summary>
        public Capture WithSection(CaptureSection section)
        {
            if (section == null) throw new ArgumentNullException(nameof(section));
            var sections = new List<CaptureSection>(ExtraSections) { section };
            return new Capture(Ids, Positions, Sh, Features, Schema, FeatureNames, CellSize, Units, LightingScale, Labels, LabelSource,
                Source, sections, ExtraHeader);
        }

        /// <summary>Rebuilds the evaluation grid from the stored ids.</summary>
        public EvaluationGrid ToGrid()
        {
            var ids = new LatticeId[PointCount];
            for (int n = 0; n < PointCount; n++) ids[n] = new LatticeId(Ids[3 * n], Ids[3 * n + 1], Ids[3 * n + 2]);
            return EvaluationGrid.FromIds(CellSize, ids);
        }
    }
}
