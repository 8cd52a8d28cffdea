using System;
using System.IO;
using Lpnn.Probes.Core.Json;

namespace Lpnn.Probes.Core.Tests.Support
{
    /// <summary>Finds the shared golden files in Tests/Data both under Mono (CI) and inside Unity, where the
    /// package path resolves through Path.GetFullPath("Packages/com.lpnn.probes/...").</summary>
    public static class TestData
    {
        private static string _directory;

        public static string Directory => _directory ?? (_directory = Locate());

        public static string PathOf(string fileName) => Path.Combine(Directory, fileName);

        public static JsonValue ReadJson(string fileName) => JsonParser.Parse(File.ReadAllText(PathOf(fileName)));

        private static string Locate()
        {
            string fromEnvironment = Environment.GetEnvironmentVariable("LPNN_TEST_DATA");
            if (!string.IsNullOrEmpty(fromEnvironment) && File.Exists(Path.Combine(fromEnvironment, "README.md"))) return fromEnvironment;
            foreach (string start in new[] { AppDomain.CurrentDomain.BaseDirectory, Environment.CurrentDirectory })
            {
                for (var dir = new DirectoryInfo(start); dir != null; dir = dir.Parent)
                {
                    string candidate = Path.Combine(dir.FullName, "Tests", "Data");
                    if (File.Exists(Path.Combine(candidate, "README.md"))) return candidate;
                }
            }
            string inUnity = Path.GetFullPath("Packages/com.lpnn.probes/Tests/Data");
            if (File.Exists(Path.Combine(inUnity, "README.md"))) return inUnity;
            throw new DirectoryNotFoundException("cannot find Tests/Data; set LPNN_TEST_DATA to the folder holding the golden files");
        }
    }
}
