#!/usr/bin/env bash
# The package's public API is what Documentation~/public-api.txt lists (issue [shape] item 2: internal by default).
# Compares it with the exported types of the assemblies built by build-csharp.sh and compile-unity-layer.sh (one Unity
# configuration; every configuration exports the same types). Exit 1 with the difference when a type became public or
# stopped being public: update the list (and Documentation~/index.md) only for a deliberate API change.
source "$(dirname "$0")/lib.sh"
cd "$REPO_ROOT"
layer="$BUILD_DIR/unity-layer"
config="$layer/unity6000.0-inference-engine-2.4.0"
tool="$BUILD_DIR/public-api.exe"
mcs -nologo -out:"$tool" "Tools~/public-api.cs" || exit 1
actual="$BUILD_DIR/public-api.actual.txt"
mono "$tool" "$layer/Lpnn.Probes.Core.dll" "$config/Lpnn.Probes.dll" "$config/Lpnn.Probes.Editor.dll" > "$actual" || exit 1
for other in "$layer"/unity*/; do
  mono "$tool" "$layer/Lpnn.Probes.Core.dll" "$other/Lpnn.Probes.dll" "$other/Lpnn.Probes.Editor.dll" | cmp -s - "$actual" \
    || { echo "public API differs in $(basename "$other") from $(basename "$config")"; exit 1; }
done
expected="Documentation~/public-api.txt"
if ! diff <(grep -v '^#' "$expected" | sed '/^$/d') "$actual"; then
  echo "the exported types differ from $expected (< listed, > built): make the type internal, or list it if the API change is deliberate"
  exit 1
fi
echo "public API: $(wc -l < "$actual") types, as $expected lists"
