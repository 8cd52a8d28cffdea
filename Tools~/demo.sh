#!/usr/bin/env bash
# The README's main job: a held-out OpenArena level, scored by the shipped model, placed with the
# error-tolerance policy, measured against the reference and a uniform grid (Documentation~/benchmarks.md).
# Installs what is missing (Python environment, OpenArena levels) first. Extra arguments go to `lpnn demo`.
source "$(dirname "$0")/lib.sh"
cd "$REPO_ROOT"
PAK=$(bash "Tools~/install-openarena.sh")
mkdir -p "$BUILD_DIR/demo"
exec "Tools~/bin/lpnn" demo --pak "$PAK" \
  --model "Packages/com.lpnn.probes/Models/lpnn_default.onnx" --out "$BUILD_DIR/demo" "$@"
