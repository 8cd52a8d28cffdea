using System;
using System.Collections.Generic;
using System.Linq;
using Lpnn.Probes.Core.Scoring;
using Lpnn.Probes.Core.Selection;

namespace Lpnn.Probes.Core.Batch
{
    /// <summary>What a batch-mode run does for each LPNN volume of the scene.</summary>
    internal enum BatchMode
    {
        /// <summary>Grid, lighting, features, scoring, selection; the probes are written to the LightProbeGroup
        /// and to a <c>*.probes.json</c> file per volume.</summary>
        Place,
        /// <summary>Grid, lighting and features only; one capture per volume is appended to the dataset folder.</summary>
        Export,
    }

    /// <summary>The arguments of <c>Lpnn.Probes.Editor.LpnnBatch.Run</c> (Documentation~/ci.md), parsed from the editor's
    /// whole command line: Unity's own flags are skipped, every <c>-lpnn…</c> flag must be known.</summary>
    internal sealed class BatchOptions
    {
        /// <summary>The command line's form; -lpnnMethod takes the table's names (Documentation~/methods.md).</summary>
        public static readonly string Usage =
            "-lpnnScene <Assets/…/Scene.unity> [-lpnnMode place|export] [-lpnnOut <folder>] [-lpnnBake] " +
            "[-lpnnVolume <GameObject name>] [-lpnnMethod " + string.Join("|", PlacementMethods.All.Select(row => row.Name)) + "] [-lpnnBackend auto|gpu|cpu] [-lpnnLabels <LightProbeGroup GameObject name>] [-lpnnSaveScene]";

        public string ScenePath { get; private set; }
        public BatchMode Mode { get; private set; } = BatchMode.Place;
        /// <summary>Where results go; null means the caller's default (a folder beside the project).</summary>
        public string OutputFolder { get; private set; }
        /// <summary>Bake the evaluation points' lighting (see the user guide for what that touches); without it, the
        /// scene's existing light probes are interpolated.</summary>
        public bool Bake { get; private set; }
        /// <summary>Only the volume on the GameObject with this name; null means every volume.</summary>
        public string VolumeName { get; private set; }
        public ScoringBackendPreference Backend { get; private set; } = ScoringBackendPreference.Auto;
        /// <summary>How place mode ranks the points for this run; null means each volume's own setting.</summary>
        public PlacementMethod? Method { get; private set; }
        /// <summary>GameObject holding the ground-truth LightProbeGroup for capture labels; null means no labels.</summary>
        public string LabelsGroupName { get; private set; }
        /// <summary>Save the scene after placing (the LightProbeGroups changed); off by default so a run never edits assets unasked.</summary>
        public bool SaveScene { get; private set; }

        public static BatchOptions Parse(IReadOnlyList<string> commandLine)
        {
            if (commandLine == null) throw new ArgumentNullException(nameof(commandLine));
            var options = new BatchOptions();
            for (int i = 0; i < commandLine.Count; i++)
            {
                string flag = commandLine[i];
                if (flag == null || !flag.StartsWith("-lpnn", StringComparison.Ordinal)) continue; // Unity's own arguments
                switch (flag)
                {
                    case "-lpnnScene": options.ScenePath = Value(commandLine, ref i); break;
                    case "-lpnnOut": options.OutputFolder = Value(commandLine, ref i); break;
                    case "-lpnnVolume": options.VolumeName = Value(commandLine, ref i); break;
                    case "-lpnnLabels": options.LabelsGroupName = Value(commandLine, ref i); break;
                    case "-lpnnBake": options.Bake = true; break;
                    case "-lpnnSaveScene": options.SaveScene = true; break;
                    case "-lpnnMode": options.Mode = ParseMode(Value(commandLine, ref i)); break;
                    case "-lpnnBackend": options.Backend = ParseBackend(Value(commandLine, ref i)); break;
                    case "-lpnnMethod": options.Method = ParseMethod(Value(commandLine, ref i)); break;
                    default: throw new LpnnException("unknown argument " + flag + "; usage: " + Usage);
                }
            }
            if (string.IsNullOrEmpty(options.ScenePath))
                throw new LpnnException("missing -lpnnScene; usage: " + Usage);
            return options;
        }

        private static string Value(IReadOnlyList<string> commandLine, ref int i)
        {
            string flag = commandLine[i];
            if (i + 1 >= commandLine.Count || string.IsNullOrEmpty(commandLine[i + 1]) || commandLine[i + 1].StartsWith("-lpnn", StringComparison.Ordinal))
                throw new LpnnException(flag + " needs a value; usage: " + Usage);
            return commandLine[++i];
        }

        private static BatchMode ParseMode(string text)
        {
            switch (text.ToLowerInvariant())
            {
                case "place": return BatchMode.Place;
                case "export": return BatchMode.Export;
                default: throw new LpnnException("-lpnnMode '" + text + "' must be place or export");
            }
        }

        private static PlacementMethod ParseMethod(string text)
        {
            if (PlacementMethods.TryParse(text, out var method)) return method;
            throw new LpnnException("-lpnnMethod '" + text + "' is not a placement method; choose one of " + PlacementMethods.Names +
                                    " (Documentation~/methods.md)");
        }

        /// <summary>The -lpnnMethod value that selects the method (what a probes file's source.method records): the table's
        /// name.</summary>
        public static string MethodName(PlacementMethod method) => PlacementMethods.Name(method);

        private static ScoringBackendPreference ParseBackend(string text)
        {
            switch (text.ToLowerInvariant())
            {
                case "auto": return ScoringBackendPreference.Auto;
                case "gpu": return ScoringBackendPreference.Gpu;
                case "cpu": return ScoringBackendPreference.Cpu;
                default: throw new LpnnException("-lpnnBackend '" + text + "' must be auto, gpu or cpu");
            }
        }
    }
}
