using System.Linq;
using Lpnn.Probes.Core.Selection;

namespace Lpnn.Probes.Editor
{
    /// <summary>The LPNN volume inspector's fixed texts (headers, buttons, help boxes, dialogs), in one place so wording is
    /// reviewed and changed together. Texts that carry numbers are composed where the numbers are.</summary>
    internal static class LpnnVolumeStyles
    {
        public const string Introduction =
            "Places light probes where baked lighting needs them: build the grid, get the lighting at every point, extract features, " +
            "score them with the model, then place the best points as probes.";
        public const string RunAll = "Run all steps";

        public const string VolumeHeader = "1. Volume";
        public const string BuildGrid = "Build grid";
        public const string LightingHeader = "2. Lighting data";
        public const string SampleLighting = "Sample lighting";
        public const string FeaturesHeader = "3. Features";
        public const string ExtractFeatures = "Extract features";
        public const string ScoringHeader = "4. Scoring";
        public const string ScorePoints = "Score evaluation points";
        public const string PlacementHeader = "5. Placement";
        public const string ExportHeader = "6. Capture export (retraining)";

        public const string ReachableNeedsSeeds =
            "The Reachable rule walks from seed points: add the scene's spawn points (or any transform on walkable ground) to " +
            "In Use Seeds, or choose Band.";

        public const string CollidersAdded = "Temporary mesh colliders will be added while rays are cast and removed afterwards.";
        public const string CollidersMissing = "Add colliders, or enable 'Add Temporary Colliders'.";
        public const string StoredScores = "Stored scores";
        public const string LegacyScoreOverrides =
            " prefab overrides of this instance hold scores saved by LPNN Probes 0.1.0 (the old serialized field 'lastScores'). " +
            "Scores are editor data now, kept outside the scene (Library/LpnnProbes/Scores); these overrides are no longer read " +
            "but stay in the scene file until removed.";
        public const string RemoveLegacyScoreOverrides = "Remove the old score overrides";
        public const string InvalidPoints = "Invalid points";
        public const string ValidityUnknownSinceScoring = "unknown (scored before validity): run Features and Scoring again";

        public const string NetworkMeasuredWorse =
            "The Network method was measured worse than Insertion at every budget from 5 % and at the tolerance " +
            "(Documentation~/benchmarks.md \"The speed/accuracy trade, every method\"); it is faster (milliseconds).";
        public const string RankByInsertion = "Rank by insertion";
        public const string FindProbes = "Find probes";
        public const string Apply = "Apply";
        public const string Clear = "Clear";
        public const string ImportProbes = "Import .probes.json…";
        public const string ImportProbesPanel = "Import probe positions (*.probes.json)";
        public const string EstimateError = "Estimate error";
        public const string FindLeaksInPreview = "Find leaks (physics rays)";
        public const string NoScoresYet = "No scores yet: run the Scoring step (or import a .probes.json).";
        public const string NoGuideScoresYet =
            "No scores yet: guided insertion takes, in each tetrahedron, the badly interpolated point the network rates highest: " +
            "run the Features and Scoring steps (or import a .probes.json).";
        public const string NoLightingYet =
            "No lighting yet: the insertion method ranks points by the Lighting data step's SH (or import a .probes.json).";
        public const string RefinedOnApply =
            "This method refines: Apply removes the probes the sampled lighting does not need (Documentation~/quality.md §5.3; " +
            "about a third fewer at the same error on the validation volumes), which takes seconds on rooms, minutes on large volumes.";
        public const string InsertionNotRankedYet =
            "The insertion method ranks the points once (about a second per 1,000 points): press 'Rank by insertion' " +
            "(Apply and Find probes also rank first).";
        public const string InsertionValidityUnknown = "Validity unknown: run the Features step to exclude points inside geometry (its rays find them).";
        public const string ScoresValidityUnknown =
            "Validity unknown (scored before validity existed): run Features and Scoring again to exclude points inside geometry.";
        public const string ErrorNeedsLighting = "Estimated error: needs the lighting of this grid (run the Lighting data step).";

        /// <summary>The policies in the order an artist should consider them (Spread first, the thesis' Percentile next), not
        /// the order of the enum, whose values are stored in scenes and only ever appended to.</summary>
        /// <summary>The methods' labels in the table's order (Documentation~/methods.md; Core.Selection.PlacementMethods.All):
        /// the enum's names are code, its values are stored in scenes.</summary>
        public static readonly string[] MethodLabels = PlacementMethods.All.Select(row => row.Label).ToArray();
        public const string Method = "Method";

        public static readonly string[] PolicyLabels = { "Spread", "Percentile (thesis)", "Top-K", "Threshold", "Tolerance (default)" };
        public const string Policy = "Policy";

        public const string ChooseFolder = "Choose…";
        public const string DatasetFolderPanel = "Dataset folder";
        public const string DatasetFolder = "Dataset folder";
        public const string DatasetInsideAssets =
            "This folder is inside Assets/: Unity will import every capture as an asset. A folder beside Assets " +
            "(the default <project>/LpnnDatasets) keeps datasets out of the project.";
        public const string SaveCapture = "Save capture…";
        public const string SaveCapturePanel = "Save capture";
        public const string AppendToDataset = "Append to dataset";

        public const string LargeGridTitle = "LPNN Probes: large grid";
        public const string SceneBakeTitle = "LPNN Probes: bake the scene's lighting?";
        public const string SceneBakeMessage =
            "Unity 2022.3 can only bake lighting at arbitrary points as part of a full bake. This will run Generate Lighting with the " +
            "scene's current Lighting Settings, replacing its lighting data (lightmaps, probes) with a fresh bake of those settings, " +
            "and read the evaluation points from it.\n\nIf your current lighting was baked with other settings, save a copy first, " +
            "or choose 'Interpolate Scene Probes', which writes nothing.";
        public const string Bake = "Bake";
        public const string Continue = "Continue";
        public const string Cancel = "Cancel";
    
        // Pinned probes (Documentation~/pins.md).
        public const string PinGroupButton = "Pin the group's probes";
        public const string ClearPinsButton = "Clear pins";
        public static string PinnedCount(int count) => count == 1 ? "1 pinned probe" : count + " pinned probes";
        /// <summary>The preview count's note on the pins among the probes Apply would place ("" when none are kept).</summary>
        public static string PinnedAmong(int count) => count == 0 ? "" : ", " + count + " of them pinned";
        public const string PinnedNotRankedYet =
            "Keep Pinned Probes is on: the insertion ranking starts from the pinned probes and skips the points within a cell of one, " +
            "so it is ranked once more for them (about a second per 1,000 points): press 'Rank by insertion' (Apply and Find probes also rank first).";
    }
}
