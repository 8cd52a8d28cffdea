using System.IO;
using UnityEngine;

namespace Lpnn.Probes.Editor
{
    /// <summary>Asset paths and folders the editor uses.</summary>
    internal static class LpnnPaths
    {
        /// <summary>The package's asset root. The repository root is the package (package.json), and the code lives
        /// under the repository folder Packages/com.lpnn.probes, hence the name twice.</summary>
        public const string PackageContent = "Packages/com.lpnn.probes/Packages/com.lpnn.probes";

        /// <summary>The shipped model and its card (repository path Packages/com.lpnn.probes/Models/).</summary>
        public const string ShippedModel = PackageContent + "/Models/lpnn_default.onnx";
        public const string ShippedModelCard = PackageContent + "/Models/lpnn_default.card.json";

        /// <summary>The Unity project folder (the parent of Assets).</summary>
        public static string ProjectRoot => Path.GetDirectoryName(Path.GetFullPath(Application.dataPath));

        /// <summary>Default dataset folder: beside Assets, so Unity never imports the captures.</summary>
        public static string DefaultDatasetFolder => Path.Combine(ProjectRoot, "LpnnDatasets");

        /// <summary>The volume's dataset folder, or the default; relative paths are relative to the project folder.</summary>
        public static string DatasetFolderFor(LpnnVolume volume)
        {
            string folder = volume.DatasetFolder;
            if (string.IsNullOrEmpty(folder)) return DefaultDatasetFolder;
            return Path.IsPathRooted(folder) ? folder : Path.GetFullPath(Path.Combine(ProjectRoot, folder));
        }

        /// <summary>True when a folder lies inside Assets/ (Unity would import every capture there as an asset).</summary>
        public static bool IsInsideAssets(string folder)
        {
            string assets = Path.GetFullPath(Application.dataPath).TrimEnd(Path.DirectorySeparatorChar) + Path.DirectorySeparatorChar;
            return (Path.GetFullPath(folder).TrimEnd(Path.DirectorySeparatorChar) + Path.DirectorySeparatorChar)
                .StartsWith(assets, System.StringComparison.OrdinalIgnoreCase);
        }
    }
}
