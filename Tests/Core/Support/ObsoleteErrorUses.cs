using System;
using System.Collections.Generic;
using System.IO;

namespace Lpnn.Probes.Core.Tests.Support
{
    /// <summary>Tools~/UnityApiSurface/Generated/obsolete-error-uses.txt (written by Tools~/api-surface/obsolete_uses.py from
    /// UnityCsReference and the needle-mirror packages): for each Unity surface ("unity-6000.5") and package surface
    /// ("inference-engine-2.4.0") that was checked, the package's uses of members that Unity version marks
    /// [Obsolete(..., true)].</summary>
    public sealed class ObsoleteErrorUses
    {
        public const string RelativePath = "Tools~/UnityApiSurface/Generated/obsolete-error-uses.txt";
        private readonly Dictionary<string, List<string>> _uses = new Dictionary<string, List<string>>();
        private readonly SortedSet<string> _unityVersions = new SortedSet<string>(StringComparer.Ordinal);

        public static ObsoleteErrorUses Read()
        {
            // Tests/Data sits in the repository root, which also holds Tools~ (under Mono and in Unity alike).
            string root = Path.GetDirectoryName(Path.GetDirectoryName(Path.GetFullPath(TestData.Directory)));
            return Parse(File.ReadAllLines(Path.Combine(root, RelativePath)));
        }

        public static ObsoleteErrorUses Parse(IEnumerable<string> lines)
        {
            var table = new ObsoleteErrorUses();
            foreach (string raw in lines)
            {
                string line = raw.Trim();
                if (line.Length == 0 || line.StartsWith("#", StringComparison.Ordinal)) continue;
                string[] fields = line.Split(new[] { ' ' }, 4);
                if (fields.Length < 4 || (fields[0] != "checked" && fields[0] != "use"))
                    throw new FormatException("unreadable line in " + RelativePath + ": '" + line + "' (rerun Tools~/api-surface/obsolete_uses.py)");
                string key = Key(fields[1], fields[2]);
                if (fields[0] == "checked")
                {
                    table._unityVersions.Add(fields[1].Substring("unity-".Length));
                    if (!table._uses.ContainsKey(key)) table._uses[key] = new List<string>();
                }
                else
                {
                    if (!table._uses.ContainsKey(key)) throw new FormatException("'use' before 'checked' for " + key + " in " + RelativePath);
                    table._uses[key].Add(fields[3]);
                }
            }
            return table;
        }

        /// <summary>Unity versions checked ("6000.5").</summary>
        public IEnumerable<string> UnityVersions => _unityVersions;

        /// <summary>Whether this pair was checked at all (a package version that was never scanned is not "clean").</summary>
        public bool WasChecked(string unityVersion, string packageSurface) => _uses.ContainsKey(Key("unity-" + unityVersion, packageSurface));

        /// <summary>The uses found ("path:line member @ where"); empty when checked and clean.</summary>
        public IReadOnlyList<string> Uses(string unityVersion, string packageSurface)
        {
            List<string> found;
            return _uses.TryGetValue(Key("unity-" + unityVersion, packageSurface), out found) ? found : (IReadOnlyList<string>)new string[0];
        }

        /// <summary>The surface label of a Package Manager identifier: "com.unity.ai.inference@2.4.0" → "inference-engine-2.4.0".</summary>
        public static string SurfaceOf(string packageAtVersion)
        {
            int at = packageAtVersion.IndexOf('@');
            if (at <= 0) throw new ArgumentException("'" + packageAtVersion + "' is not name@version");
            string name = packageAtVersion.Substring(0, at), version = packageAtVersion.Substring(at + 1);
            if (name == "com.unity.ai.inference") return "inference-engine-" + version;
            if (name == "com.unity.sentis") return "sentis-" + version;
            throw new ArgumentException("'" + name + "' is neither com.unity.ai.inference nor com.unity.sentis");
        }

        private static string Key(string unity, string package) => unity + " " + package;
    }
}
