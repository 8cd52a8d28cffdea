using System.IO;
using Lpnn.Probes.Core;
using Lpnn.Probes.Core.Captures;
using Lpnn.Probes.Core.Json;
using Lpnn.Probes.Core.Labels;
using UnityEngine;

namespace Lpnn.Probes.Editor
{
    /// <summary>Exports a volume's grid, lighting and features as a capture (Documentation~/file-formats.md) for retraining,
    /// with labels from the ground-truth LightProbeGroup when one is assigned, and the in-use rule it was built with
    /// (<see cref="InUseCaptureSource"/>). Files are written atomically by the core:
    /// Save replaces one named file, Append always creates a new file and never alters existing captures.</summary>
    public static class CaptureExport
    {
        /// <summary>The capture of the session's current results; <paramref name="labelSummary"/> describes the labels.</summary>
        public static Capture Build(LpnnVolume volume, LpnnSession session, out string labelSummary)
        {
            if (session.Grid == null || session.Sh == null || session.Features == null)
                throw new LpnnException("a capture needs the grid, the lighting data and the features of this volume; run those steps first");
            var source = JsonValue.NewObject();
            source.Set("tool", JsonValue.From("com.lpnn.probes (Unity editor)"));
            source.Set("unity", JsonValue.From(Application.unityVersion));
            source.Set("scene", JsonValue.From(volume.gameObject.scene.path));
            source.Set("volume", JsonValue.From(volume.name));
            source.Set("lighting", JsonValue.From(session.LightingDescription));
            // The in-use rule's keys go into the same source object; All adds the in_use section (Documentation~/in-use.md).
            var capture = InUseCaptureSource.Record(Capture.FromGrid(session.Grid, session.Sh, session.Features, source), source, session.InUse);
            var truth = volume.GroundTruthGroup;
            if (truth == null)
            {
                labelSummary = "no labels (no ground-truth LightProbeGroup assigned)";
                return capture;
            }
            var world = UnityCoreConversions.LocalToWorld(truth.transform, truth.probePositions);
            var labels = ProbeLabeler.Label(session.Grid, world);
            labelSummary = labels.PositivePoints + " positive points from " + labels.ProbesMatched + " of " + world.Length + " ground-truth probes" +
                           (labels.ProbesOutside > 0 ? " (" + labels.ProbesOutside + " lie outside the volume)" : "");
            return capture.WithLabels(labels.Labels, "probes:LightProbeGroup '" + truth.name + "'");
        }

        /// <summary>Writes (or atomically replaces) one capture file (the .lpnncap extension is added when missing); returns the path.</summary>
        public static string Save(LpnnVolume volume, LpnnSession session, string path, out string labelSummary)
        {
            var capture = Build(volume, session, out labelSummary);
            if (!path.EndsWith(CaptureFile.Extension, System.StringComparison.OrdinalIgnoreCase)) path += CaptureFile.Extension;
            CaptureFile.Save(path, capture);
            return path;
        }

        /// <summary>Adds a new capture file to the dataset folder (stem, stem-2, …); returns its path.</summary>
        public static string Append(LpnnVolume volume, LpnnSession session, string folder, string stem, out string labelSummary)
        {
            var capture = Build(volume, session, out labelSummary);
            Directory.CreateDirectory(folder);
            return CaptureFile.Append(folder, capture, Stem(stem));
        }

        /// <summary>Default file stem: scene and volume name.</summary>
        public static string DefaultStem(LpnnVolume volume)
        {
            string scene = volume.gameObject.scene.name;
            return (string.IsNullOrEmpty(scene) ? "scene" : scene) + "_" + volume.name;
        }

        private static string Stem(string name)
        {
            if (string.IsNullOrEmpty(name)) return "capture";
            return name.EndsWith(CaptureFile.Extension, System.StringComparison.OrdinalIgnoreCase)
                ? name.Substring(0, name.Length - CaptureFile.Extension.Length)
                : name;
        }
    }
}
