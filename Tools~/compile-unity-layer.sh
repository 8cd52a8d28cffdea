#!/usr/bin/env bash
# Compile check of the Unity layer without Unity: compiles the signature-only API surface in Tools~/UnityApiSurface into
# stand-in assemblies, then Runtime/Core, Runtime, Editor, Tests/Editor and the CorridorDemo sample against them with Mono's
# mcs (C# 7.2, warnings as errors), in four configurations (Unity 2022.3 / 6000.0 × Sentis 2.1 / Inference Engine 2.2,
# plus 2022.3 without any inference package), and Tests/Core against NUnit. This proves that the code compiles against the
# declared surface — not that it runs or behaves correctly inside Unity (Documentation~/unity-api-surface.md).
source "$(dirname "$0")/lib.sh"
PKG="$REPO_ROOT/Packages/com.lpnn.probes"
SURFACE="$REPO_ROOT/Tools~/UnityApiSurface"
OUT="$BUILD_DIR/unity-layer"
NUNIT_DLL=/usr/lib/cli/nunit.framework-2.6.3/nunit.framework.dll
command -v mcs >/dev/null 2>&1 || die "mcs not found (run Tools~/install-system.sh)"
[ -f "$NUNIT_DLL" ] || die "NUnit 2.6 framework not found at $NUNIT_DLL (run Tools~/install-system.sh)"
rm -rf "$OUT"; mkdir -p "$OUT"

BASE=(mcs -nologo -langversion:7.2 -target:library -r:System.dll -r:System.Core.dll -r:System.Numerics.dll -r:System.Numerics.Vectors.dll)
STRICT=(-warn:4 -warnaserror+ -nowarn:1591)
compiled=0

sources() {  # sources DIR [find options...] : sorted .cs files
  local dir="$1"; shift
  find "$dir" -name '*.cs' "$@" | sort
}

build() {  # build OUTPUT.dll "description" mcs-args... : compiles, counts, reports
  local output="$1" description="$2"; shift 2
  if ! "${BASE[@]}" -out:"$output" "$@"; then
    log "FAILED: $description"
    exit 1
  fi
  compiled=$((compiled + 1))
  log "ok  $description"
}

# The engine-agnostic core and its NUnit tests (configuration-independent).
mapfile -t core < <(sources "$PKG/Runtime/Core")
build "$OUT/Lpnn.Probes.Core.dll" "Runtime/Core (Lpnn.Probes.Core)" "${STRICT[@]}" "${core[@]}"
mapfile -t core_tests < <(sources "$REPO_ROOT/Tests/Core")
build "$OUT/Lpnn.Probes.Core.Tests.dll" "Tests/Core against NUnit" "${STRICT[@]}" -r:"$OUT/Lpnn.Probes.Core.dll" -r:"$NUNIT_DLL" "${core_tests[@]}"

mapfile -t runtime < <(sources "$PKG/Runtime" -not -path "$PKG/Runtime/Core/*")
mapfile -t editor < <(sources "$PKG/Editor")
mapfile -t editor_tests < <(sources "$REPO_ROOT/Tests/Editor")
mapfile -t sample < <(sources "$REPO_ROOT/Samples~/CorridorDemo")
mapfile -t engine_stubs < <(sources "$SURFACE/UnityEngine")
mapfile -t editor_stubs < <(sources "$SURFACE/UnityEditor")
mapfile -t sentis_stubs < <(sources "$SURFACE/Sentis")
mapfile -t runner_stubs < <(sources "$SURFACE/TestRunner")

configure() {  # configure NAME UNITY(2022.3|6000.0) INFERENCE(sentis|inference-engine|none)
  local name="$1" unity="$2" inference="$3" dir="$OUT/$1"
  mkdir -p "$dir"
  log "configuration $name"
  local unity_defines="-define:UNITY_2022_2_OR_NEWER;UNITY_2022_3_OR_NEWER"
  [ "$unity" = "6000.0" ] && unity_defines="$unity_defines;UNITY_2023_1_OR_NEWER;UNITY_2023_2_OR_NEWER;UNITY_6000_0_OR_NEWER"

  build "$dir/UnityEngine.dll" "  surface UnityEngine ($unity)" "$unity_defines" "${engine_stubs[@]}"
  build "$dir/UnityEditor.dll" "  surface UnityEditor ($unity)" "$unity_defines" -r:"$dir/UnityEngine.dll" "${editor_stubs[@]}"
  build "$dir/UnityEngine.TestRunner.dll" "  surface UnityEngine.TestRunner" -r:"$dir/UnityEngine.dll" "${runner_stubs[@]}"
  local inference_ref=() inference_define=""
  case "$inference" in
    sentis)
      build "$dir/Unity.Sentis.dll" "  surface Unity.Sentis 2.1" -r:"$dir/UnityEngine.dll" "${sentis_stubs[@]}"
      inference_ref=(-r:"$dir/Unity.Sentis.dll"); inference_define=";LPNN_SENTIS" ;;
    inference-engine)
      build "$dir/Unity.InferenceEngine.dll" "  surface Unity.InferenceEngine 2.2" -define:LPNN_STUB_INFERENCE_ENGINE -r:"$dir/UnityEngine.dll" "${sentis_stubs[@]}"
      inference_ref=(-r:"$dir/Unity.InferenceEngine.dll"); inference_define=";LPNN_INFERENCE_ENGINE" ;;
  esac

  # Runtime: UnityEngine only, no UNITY_EDITOR and no UnityEditor reference, as in a player build.
  build "$dir/Lpnn.Probes.dll" "  Runtime (Lpnn.Probes)" "${STRICT[@]}" "$unity_defines" \
    -r:"$dir/UnityEngine.dll" -r:"$OUT/Lpnn.Probes.Core.dll" "${runtime[@]}"
  local editor_defines="$unity_defines;UNITY_EDITOR$inference_define"
  build "$dir/Lpnn.Probes.Editor.dll" "  Editor (Lpnn.Probes.Editor)" "${STRICT[@]}" "$editor_defines" \
    -r:"$dir/UnityEngine.dll" -r:"$dir/UnityEditor.dll" -r:"$OUT/Lpnn.Probes.Core.dll" -r:"$dir/Lpnn.Probes.dll" "${inference_ref[@]}" "${editor[@]}"
  build "$dir/Lpnn.Probes.Editor.Tests.dll" "  Tests/Editor (Lpnn.Probes.Editor.Tests)" "${STRICT[@]}" "$editor_defines;UNITY_INCLUDE_TESTS" \
    -r:"$dir/UnityEngine.dll" -r:"$dir/UnityEditor.dll" -r:"$dir/UnityEngine.TestRunner.dll" -r:"$NUNIT_DLL" \
    -r:"$OUT/Lpnn.Probes.Core.dll" -r:"$dir/Lpnn.Probes.dll" -r:"$dir/Lpnn.Probes.Editor.dll" "${editor_tests[@]}"
  build "$dir/Lpnn.Probes.Samples.CorridorDemo.dll" "  Samples~/CorridorDemo" "${STRICT[@]}" "$editor_defines" \
    -r:"$dir/UnityEngine.dll" -r:"$dir/UnityEditor.dll" -r:"$OUT/Lpnn.Probes.Core.dll" -r:"$dir/Lpnn.Probes.dll" \
    -r:"$dir/Lpnn.Probes.Editor.dll" "${sample[@]}"
}

configure unity2022.3-sentis2.1 2022.3 sentis
configure unity6000.0-inferenceengine2.2 6000.0 inference-engine
configure unity6000.0-sentis2.1 6000.0 sentis
configure unity2022.3-no-inference-package 2022.3 none

log "compile-unity-layer: $compiled assemblies compiled in 4 configurations (surface: Tools~/UnityApiSurface); compilation only, nothing ran in Unity"
