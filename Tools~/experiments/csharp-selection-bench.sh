#!/usr/bin/env bash
# Times the C# core's selection paths under Mono on synthetic lattices of ~10^4, 10^5 and 10^6 points
# and the insertion ranking's parts that run without Unity (Documentation~/benchmarks.md "The C# core under Mono"). Usage: bash Tools~/experiments/csharp-selection-bench.sh [--batched] [n ...]  (n^3 points each)
# --apply CAPTURE...: the whole default selection of a volume's Apply (insertion refined in batches, tau = 0.05) on each
# capture, the Apply rehearsal's run with Python's tetrahedraliser over a pipe: seconds per stage, seconds waiting on the
# tetrahedraliser, tetrahedralisations per stage, probes kept (benchmarks.md "The C# core under Mono"; Tools~/experiments/SelectionBench/ApplyBench.cs).
source "$(dirname "$0")/../lib.sh"
cd "$REPO_ROOT"
bash "Tools~/build-csharp.sh" > /dev/null
mcs -nologo -langversion:7.2 -optimize+ -out:"$BUILD_DIR/SelectionBench.exe" -r:System.Numerics.dll -r:System.Numerics.Vectors.dll \
  -r:"$BUILD_DIR/Lpnn.Probes.Core.dll" -r:"$BUILD_DIR/Lpnn.Probes.Core.Tests.dll" \
  "Tools~/experiments/SelectionBench/SelectionBench.cs" "Tools~/experiments/SelectionBench/ApplyBench.cs"
if [ "${1:-}" = "--apply" ]; then
  shift
  [ "$#" -ge 1 ] || die "usage: bash Tools~/experiments/csharp-selection-bench.sh --apply CAPTURE.lpnncap..."
  PY=$(bash "Tools~/setup-python.sh")
  server="$REPO_ROOT/Training~/tests/quality/rehearsal_tetrahedralizer.py"
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
  for capture in "$@"; do
    capture=$(cd "$(dirname "$capture")" && pwd)/$(basename "$capture")
    [ -f "$capture" ] || die "no capture $capture"
    printf "#!/bin/sh\nPYTHONPATH='%s' exec '%s' '%s' '%s'\n" "$TRAINING_DIR" "$PY" "$server" "$capture" > "$work/tetrahedralizer.sh"
    (cd "$BUILD_DIR" && mono --server SelectionBench.exe --apply "$capture" "$work/tetrahedralizer.sh")
  done
  exit 0
fi
cd "$BUILD_DIR" && mono --server SelectionBench.exe "$@"
