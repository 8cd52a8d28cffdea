#!/usr/bin/env bash
# Times the C# core's selection paths under Mono on synthetic lattices of ~10^4, 10^5 and 10^6 points
# and the insertion ranking's parts that run without Unity (Documentation~/benchmarks.md §7.4). Usage: bash Tools~/csharp-selection-bench.sh [--batched] [n ...]  (n^3 points each)
source "$(dirname "$0")/lib.sh"
cd "$REPO_ROOT"
bash "Tools~/build-csharp.sh" > /dev/null
mcs -nologo -langversion:7.2 -optimize+ -out:"$BUILD_DIR/SelectionBench.exe" -r:System.Numerics.dll -r:System.Numerics.Vectors.dll \
  -r:"$BUILD_DIR/Lpnn.Probes.Core.dll" -r:"$BUILD_DIR/Lpnn.Probes.Core.Tests.dll" \
  "Tools~/SelectionBench/SelectionBench.cs"
cd "$BUILD_DIR" && mono --server SelectionBench.exe "$@"
