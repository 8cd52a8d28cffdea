#!/usr/bin/env bash
# Compiles and runs JsonLibraryComparison.cs against the built core and Debian's Json.NET (see the .cs file's header).
source "$(dirname "$0")/../../lib.sh"
NEWTONSOFT=/usr/lib/cli/Newtonsoft.Json-5.0/Newtonsoft.Json.dll
[ -f "$NEWTONSOFT" ] || die "Json.NET not found at $NEWTONSOFT (apt-get install libnewtonsoft-json-cil-dev)"
bash "$REPO_ROOT/Tools~/build-csharp.sh" >/dev/null
OUT="$BUILD_DIR/json-comparison"; mkdir -p "$OUT"
cp "$BUILD_DIR/Lpnn.Probes.Core.dll" "$NEWTONSOFT" "$OUT/"
mcs -nologo -langversion:7.2 -out:"$OUT/JsonLibraryComparison.exe" -r:"$OUT/Lpnn.Probes.Core.dll" -r:"$OUT/Newtonsoft.Json.dll" \
  -r:System.Numerics.dll "$(dirname "$0")/JsonLibraryComparison.cs"
files=$(ls "$REPO_ROOT"/Tests/Data/*.json "$REPO_ROOT/Packages/com.lpnn.probes/Models/lpnn_default.card.json" | paste -sd';')
mono "$OUT/JsonLibraryComparison.exe" "$files" "$REPO_ROOT/Tests/Data/capture_golden.lpnncap"
