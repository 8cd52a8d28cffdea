using System.Runtime.CompilerServices;

// Internal by default: the public API is what Documentation~/index.md documents (pinned by Documentation~/public-api.txt);
// the test assemblies and the layer above reach the rest.
[assembly: InternalsVisibleTo("Lpnn.Probes.Editor")]
[assembly: InternalsVisibleTo("Lpnn.Probes.Editor.Tests")]
