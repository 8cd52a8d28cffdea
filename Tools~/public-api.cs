// Lists the exported (public) types of the package's assemblies, one "Assembly: Namespace.Type" line each, sorted:
// what Documentation~/public-api.txt pins (Tools~/check-public-api.sh compares them). Loads each assembly with its
// neighbours (the generated Unity API surfaces) as references.
using System;
using System.Collections.Generic;
using System.IO;
using System.Linq;
using System.Reflection;

public static class PublicApi
{
    public static int Main(string[] paths)
    {
        var folders = paths.Select(p => Path.GetDirectoryName(Path.GetFullPath(p))).Distinct().ToList();
        AppDomain.CurrentDomain.AssemblyResolve += (sender, args) =>
        {
            string file = new AssemblyName(args.Name).Name + ".dll";
            foreach (string folder in folders.Concat(paths.Select(p => Path.GetDirectoryName(Path.GetFullPath(Path.Combine(p, "..", "x"))))))
            {
                string candidate = Path.Combine(folder, file);
                if (File.Exists(candidate)) return Assembly.LoadFrom(candidate);
            }
            return null;
        };
        var lines = new List<string>();
        foreach (string path in paths)
        {
            var assembly = Assembly.LoadFrom(path);
            string name = assembly.GetName().Name;
            lines.AddRange(assembly.GetExportedTypes().Select(t => name + ": " + t.FullName.Replace('+', '.')));
        }
        lines.Sort(StringComparer.Ordinal);
        foreach (string line in lines) Console.WriteLine(line);
        return 0;
    }
}
