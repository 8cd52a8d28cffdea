using System.Runtime.CompilerServices;

// Internal by default: the public API is what Documentation~/index.md documents (pinned by Documentation~/public-api.txt);
// the test assemblies and the layers above (the Unity runtime and editor assemblies) reach the rest.
[assembly: InternalsVisibleTo("Lpnn.Probes")]
[assembly: InternalsVisibleTo("Lpnn.Probes.Editor")]
[assembly: InternalsVisibleTo("Lpnn.Probes.Core.Tests")]
[assembly: InternalsVisibleTo("Lpnn.Probes.Editor.Tests")]
// The selection benchmark (Tools~/experiments/csharp-selection-bench.sh) times internal selection paths, as the tests reach them.
[assembly: InternalsVisibleTo("SelectionBench")]
// The JSON library comparison (Tools~/experiments/json-comparison/run.sh, Documentation~/file-formats.md) reads with the
// internal Core/Json reader and writer.
[assembly: InternalsVisibleTo("JsonLibraryComparison")]
// The golden-file writer (Tools~/golden/GoldenWriter.cs, run by Tools~/regenerate-golden.sh) builds the C#-side cases from
// internal tables (the ray direction sets of Documentation~/features.md).
[assembly: InternalsVisibleTo("GoldenWriter")]
