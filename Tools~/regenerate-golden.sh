#!/usr/bin/env bash
# Regenerates the golden files in Tests/Data. Deliberate only: review the diff, and bump the schema or
# format version when a contract changed. Tests never run this.
source "$(dirname "$0")/lib.sh"
cd "$REPO_ROOT"
bash "Tools~/build-csharp.sh"
mcs -nologo -langversion:7.2 -r:System.Numerics.dll -r:System.Numerics.Vectors.dll \
  -r:"$BUILD_DIR/Lpnn.Probes.Core.dll" -r:"$BUILD_DIR/Lpnn.Probes.Core.Tests.dll" -r:"$BUILD_DIR/nunit.framework.dll" \
  -out:"$BUILD_DIR/GoldenWriter.exe" "Tools~/golden/GoldenWriter.cs"
(cd "$BUILD_DIR" && MONO_PATH="$BUILD_DIR" mono GoldenWriter.exe "$REPO_ROOT/Tests/Data")
PY=$(bash "Tools~/setup-python.sh")
PYTHONPATH="$TRAINING_DIR" "$PY" "Tools~/golden/make_sh_golden.py" "$REPO_ROOT/Tests/Data"
PYTHONPATH="$TRAINING_DIR" "$PY" "Tools~/golden/make_quality_golden.py" "$REPO_ROOT/Tests/Data"
PYTHONPATH="$TRAINING_DIR" "$PY" "Tools~/golden/make_insertion_golden.py" "$REPO_ROOT/Tests/Data"
PYTHONPATH="$TRAINING_DIR" "$PY" "Tools~/golden/make_batched_refinement_golden.py" "$REPO_ROOT/Tests/Data"
PYTHONPATH="$TRAINING_DIR" "$PY" "Tools~/golden/make_leak_aware_golden.py" "$REPO_ROOT/Tests/Data"
python3 "Tools~/golden/make_leaks_golden.py"
python3 "Tools~/golden/make_in_use_golden.py"
python3 "Tools~/golden/make_tet_numbering_golden.py" "$REPO_ROOT/Tests/Data"
