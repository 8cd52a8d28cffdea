#!/usr/bin/env bash
# Reproduces figures of Documentation~/benchmarks.md on this machine (each part prints its own; minutes on 2 cores:
# run it on an otherwise idle machine). Writes everything under Build~/benchmarks/ and prints the figures.
#   bash Tools~/experiments/benchmarks.sh [scenes] [reference] [model] [report]   (default: all)
# The inputs are the documented ones unless these are set (the smoke test, tests/tools/test_benchmarks_sh.py, sets tiny
# ones): OUT, SCENES (levels), ROOM_CELL, REFERENCE_LEVELS (LEVEL:CELL ...), WORKERS (process counts),
# MODEL_BENCH_OPTIONS (extra options of `lpnn model bench`).
source "$(dirname "$0")/../lib.sh"
cd "$REPO_ROOT"
PY=$(bash "Tools~/setup-python.sh")
PAK=$(bash "Tools~/install-openarena.sh")
OUT="${OUT:-$BUILD_DIR/benchmarks}"
SCENES="${SCENES:-czest2ctf wrackdm17 suspended}"
ROOM_CELL="${ROOM_CELL:-0.28}"
REFERENCE_LEVELS="${REFERENCE_LEVELS:-oa_dm1:1.1 oa_rpg3dm2:1.5 dm4ish:1.22 oa_dm6:1.17}"
WORKERS="${WORKERS:-1 2}"
MODEL_BENCH_OPTIONS="${MODEL_BENCH_OPTIONS:-}"
MODEL="Packages/com.lpnn.probes/Models/lpnn_default.onnx"
mkdir -p "$OUT"
lpnn() { "$REPO_ROOT/Tools~/bin/lpnn" "$@"; }
parts=("$@")
want() { [ ${#parts[@]} -eq 0 ] && return 0; local p; for p in "${parts[@]}"; do [ "$p" = "$1" ] && return 0; done; return 1; }

if want scenes; then
  log "scenes: the three largest levels of the pak at the default cell (import + features)"
  for level in $SCENES; do
    lpnn scene import "$level" --point-limit 3000000 --out "$OUT/$level.lpnncap"
  done
fi

if want reference; then
  log "fast reference: ~5,000 candidates, every budget (one process, then two)"
  PYTHONPATH="$TRAINING_DIR" "$PY" -c "from lpnn.core.analytic_scene import AnalyticScene; from lpnn.core.capture_file import write_capture; \
write_capture('$OUT/room.lpnncap', AnalyticScene.random(7, cell_size=$ROOM_CELL, room_size=(6, 3, 5)).capture())"
  # Real levels at the cell that gives them 4,862-4,938 candidates.
  captures=(room)
  for spec in $REFERENCE_LEVELS; do
    level=${spec%%:*}; cell=${spec##*:}
    lpnn scene import "$level" --cell "$cell" --drop-unlit --out "$OUT/$level@$cell.lpnncap" > /dev/null
    captures+=("$level@$cell")
  done
  for capture in "${captures[@]}"; do
    for workers in $WORKERS; do
      TIMEFORMAT="$capture: fast reference, $workers process(es), read to write: %R s wall"
      time lpnn place "$OUT/$capture.lpnncap" --method fast-reference --budget 0.2 --workers "$workers" \
        --out "$OUT/$capture.probes.json" > /dev/null
    done
  done
fi

if want model; then
  log "model: onnxruntime scoring time of the shipped model and training throughput"
  # shellcheck disable=SC2086  # MODEL_BENCH_OPTIONS: words, on purpose
  lpnn model bench "$MODEL" $MODEL_BENCH_OPTIONS
fi

if want report; then
  lpnn recipe report "$MODEL" --check "Documentation~/benchmarks.md"
fi
