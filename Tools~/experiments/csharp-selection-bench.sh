#!/usr/bin/env bash
# Times the C# core's selection paths under Mono on synthetic lattices of ~10^4, 10^5 and 10^6 points
# and the insertion ranking's parts that run without Unity (Documentation~/benchmarks.md "The C# core under Mono"). Usage: bash Tools~/experiments/csharp-selection-bench.sh [--batched] [n ...]  (n^3 points each)
# --apply [--leaks ignore] [--rays csharp|embree] [--no-memo] [--no-refills] [--tetrahedralised-rounds] [--serial] [--compare] CAPTURE...: the whole default selection of a
# volume's Apply (insertion refined in batches, tau = 0.05) on each capture, the Apply rehearsal's run with Python's
# tetrahedraliser over a pipe: seconds per stage, seconds waiting on the tetrahedraliser, tetrahedralisations and rays per
# stage, probes kept (benchmarks.md "The C# core under Mono"; Tools~/experiments/SelectionBench/ApplyBench.cs).
# Leak-aware by default, as a volume's Apply (Avoid light leaks), on OpenArena captures (their level is read as `lpnn
# place` reads it): --rays csharp (the default) casts through a C# hierarchy over the level's triangles
# (write_capture_triangles.py; Tests/Core/Support/TriangleSoupRaycaster.cs, standing in for Unity's physics), --rays embree
# through Python's Embree over a pipe (embree_raycaster_server.py: lpnn place's own answers, for parity). --leaks ignore:
# leak-blind (the toggle off); --no-memo: every segment cast anew (no SegmentMemo); --no-refills: the refinement
# tetrahedralises every trial and commit, as before the star refills (quality.md §5.3); --tetrahedralised-rounds: every
# insertion round tetrahedralised instead of derived from the last round's tetrahedra (quality.md §5.1 step 6; the two
# must keep the same probes); --serial: every
# per-point pass on one core (Numerics/ParallelChunks forced to one chunk: the same probes, for a same-build A/B of the
# parallel passes); --compare: also runs `lpnn place
# CAPTURE --tolerance 0.05` (with the same --leaks) and prints whether the C# probes are its probes.
source "$(dirname "$0")/../lib.sh"
cd "$REPO_ROOT"
bash "Tools~/build-csharp.sh" > /dev/null
mcs -nologo -langversion:7.2 -optimize+ -out:"$BUILD_DIR/SelectionBench.exe" -r:System.Numerics.dll -r:System.Numerics.Vectors.dll \
  -r:"$BUILD_DIR/Lpnn.Probes.Core.dll" -r:"$BUILD_DIR/Lpnn.Probes.Core.Tests.dll" \
  "Tools~/experiments/SelectionBench/SelectionBench.cs" "Tools~/experiments/SelectionBench/ApplyBench.cs" \
  "Tools~/experiments/SelectionBench/PipeRaycaster.cs"
if [ "${1:-}" = "--apply" ]; then
  shift
  leaks=avoid rays=csharp memo=() refills=() meshes=() serial=() compare=0
  while [ "$#" -ge 1 ]; do
    case "$1" in
      --leaks) [ "$#" -ge 2 ] || die "--leaks needs avoid or ignore"; leaks=$2; shift 2 ;;
      --rays) [ "$#" -ge 2 ] || die "--rays needs csharp or embree"; rays=$2; shift 2 ;;
      --no-memo) memo=(--no-memo); shift ;;
      --no-refills) refills=(--no-refills); shift ;;
      --serial) serial=(--serial); shift ;;
      --tetrahedralised-rounds) meshes=("$1"); shift ;;
      --compare) compare=1; shift ;;
      *) break ;;
    esac
  done
  [ "$leaks" = avoid ] || [ "$leaks" = ignore ] || die "--leaks must be avoid or ignore, not $leaks"
  [ "$rays" = csharp ] || [ "$rays" = embree ] || die "--rays must be csharp or embree, not $rays"
  [ "$leaks" = avoid ] || [ "${#memo[@]}" -eq 0 ] || die "--no-memo is for the leak-aware Apply (--leaks avoid)"
  [ "$#" -ge 1 ] || die "usage: bash Tools~/experiments/csharp-selection-bench.sh --apply [--leaks ignore] [--rays csharp|embree] [--no-memo] [--no-refills] [--tetrahedralised-rounds] [--serial] [--compare] CAPTURE.lpnncap..."
  PY=$(bash "Tools~/setup-python.sh")
  server="$REPO_ROOT/Training~/tests/quality/rehearsal_tetrahedralizer.py"
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
  for capture in "$@"; do
    capture=$(cd "$(dirname "$capture")" && pwd)/$(basename "$capture")
    [ -f "$capture" ] || die "no capture $capture"
    printf "#!/bin/sh\nPYTHONPATH='%s' exec '%s' '%s' '%s'\n" "$TRAINING_DIR" "$PY" "$server" "$capture" > "$work/tetrahedralizer.sh"
    options=("${refills[@]}" "${meshes[@]}" "${serial[@]}")
    if [ "$leaks" = avoid ] && [ "$rays" = csharp ]; then
      PYTHONPATH="$TRAINING_DIR" "$PY" "Tools~/experiments/SelectionBench/write_capture_triangles.py" "$capture" "$work/triangles.bin" ||
        die "$capture: no level geometry for the leak-aware Apply (--leaks ignore runs the leak-blind one)"
      options+=(--geometry "$work/triangles.bin" "${memo[@]}")
    elif [ "$leaks" = avoid ]; then
      printf "#!/bin/sh\nPYTHONPATH='%s' exec '%s' '%s' '%s'\n" "$TRAINING_DIR" "$PY" "$REPO_ROOT/Tools~/experiments/SelectionBench/embree_raycaster_server.py" \
        "$capture" > "$work/raycaster.sh"
      options+=(--embree "$work/raycaster.sh" "${memo[@]}")
    fi
    if [ "$compare" = 1 ]; then
      PYTHONPATH="$TRAINING_DIR" "$PY" -m lpnn.cli.main place "$capture" --tolerance 0.05 --leaks "$leaks" --out "$work/place.probes.json" \
        2> "$work/place.log" || { cat "$work/place.log" >&2; die "lpnn place failed on $capture"; }
      options+=(--expect "$work/place.probes.json")
    fi
    (cd "$BUILD_DIR" && mono --server SelectionBench.exe --apply "$capture" "$work/tetrahedralizer.sh" "${options[@]}")
  done
  exit 0
fi
cd "$BUILD_DIR" && mono --server SelectionBench.exe "$@"
