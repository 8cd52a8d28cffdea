using System;
using System.Collections.Generic;

namespace Lpnn.Probes.Core.Features
{
    /// <summary>A named, versioned, ordered list of per-point features (Documentation~/features.md).</summary>
    public sealed class FeatureSchema
    {
        public string Id { get; }
        public IReadOnlyList<string> Names { get; }
        public int Count => Names.Count;

        /// <summary>False for legacy layouts that can be read and trained on but are never extracted.</summary>
        public bool Extractable { get; }

        private FeatureSchema(string id, string[] names, bool extractable)
        {
            Id = id;
            Names = Array.AsReadOnly(names);
            Extractable = extractable;
        }

        public static readonly FeatureSchema LpnnV1 = new FeatureSchema("lpnn.features.v1", new[]
        {
            "log_luminance", "chroma_co", "chroma_cg", "directionality", "light_variance",
            "rgb_variance_r", "rgb_variance_g", "rgb_variance_b", "boundary",
            "change_1", "change_2", "change_4", "curvature_1", "curvature_2", "curvature_4",
            "occlusion_near", "occlusion_far", "nearest_surface", "normal_spread",
        }, true);

        public static readonly FeatureSchema Thesis30 = new FeatureSchema("lpnn.thesis30", Thesis30Names(), false);

        private static string[] Thesis30Names()
        {
            var names = new List<string>();
            for (int d = 0; d < 6; d++)
                foreach (char c in "rgba")
                    names.Add("sh_d" + d + "_" + c);
            names.AddRange(new[] { "light_variance", "normal_variance", "occlusion_factor", "rgb_variance_r", "rgb_variance_g", "rgb_variance_b" });
            return names.ToArray();
        }

        public static IReadOnlyList<FeatureSchema> All { get; } = Array.AsReadOnly(new[] { LpnnV1, Thesis30 });

        /// <summary>The known schema with this id, or null.</summary>
        public static FeatureSchema ById(string id)
        {
            foreach (var schema in All)
                if (schema.Id == id) return schema;
            return null;
        }

        public int IndexOf(string name)
        {
            for (int f = 0; f < Names.Count; f++)
                if (Names[f] == name) return f;
            return -1;
        }

        /// <summary>True when <paramref name="names"/> is exactly this schema's list.</summary>
        public bool NamesMatch(IReadOnlyList<string> names)
        {
            if (names == null || names.Count != Names.Count) return false;
            for (int f = 0; f < Names.Count; f++)
                if (names[f] != Names[f]) return false;
            return true;
        }
    }
}
