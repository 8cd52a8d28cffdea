#!/usr/bin/env bash
# Compile check of the Unity layer without Unity: compiles the signature-only API surfaces generated from the real
# UnityCsReference branches and inference packages (Tools~/UnityApiSurface/Generated, by Tools~/api-surface/generate.py)
# into stand-in assemblies, then Runtime/Core, Runtime, Editor, Tests/Editor and the CorridorDemo sample against them with
# Mono's mcs (C# 7.2, warnings as errors, so any [Obsolete] use fails) in every configuration of the supported matrix, and
# Tests/Core against NUnit. This proves that the code compiles against those signatures — not that it runs or behaves
# correctly inside Unity (Documentation~/unity-api-surface.md).
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

# Mono 6.8's mcs reads a digit separator as a zero (250_000 compiles to 2500000; Unity's Roslyn reads 250000), so the
# same literal would mean one thing in Unity and another in every Mono test: refuse them in our sources.
if separators=$(grep -rnE '(^|[^A-Za-z0-9_"])[0-9]+(_[0-9]+)+([^A-Za-z0-9_]|$)' --include='*.cs' \
    "$PKG/Runtime" "$PKG/Editor" "$REPO_ROOT/Tests" "$REPO_ROOT/Samples~" "$REPO_ROOT/Tools~/experiments/SelectionBench" "$REPO_ROOT/Tools~/golden" \
    | grep -v '"[^"]*[0-9]_[0-9][^"]*"'); then
  die "digit separators in numeric literals (mcs reads 250_000 as 2500000; write 250000):
$separators"
fi

# The engine-agnostic core and its NUnit tests (configuration-independent).
mapfile -t core < <(sources "$PKG/Runtime/Core")
build "$OUT/Lpnn.Probes.Core.dll" "Runtime/Core (Lpnn.Probes.Core)" "${STRICT[@]}" "${core[@]}"
mapfile -t core_tests < <(sources "$REPO_ROOT/Tests/Core")
build "$OUT/Lpnn.Probes.Core.Tests.dll" "Tests/Core against NUnit" "${STRICT[@]}" -r:"$OUT/Lpnn.Probes.Core.dll" -r:"$NUNIT_DLL" "${core_tests[@]}"

mapfile -t runtime < <(sources "$PKG/Runtime" -not -path "$PKG/Runtime/Core/*")
mapfile -t editor < <(sources "$PKG/Editor")
mapfile -t editor_tests < <(sources "$REPO_ROOT/Tests/Editor")
mapfile -t sample < <(sources "$REPO_ROOT/Samples~/CorridorDemo")
GENERATED="$SURFACE/Generated"
runner_stubs=("$SURFACE/TestRunner/UnityTestAttribute.cs")
[ -f "$GENERATED/SOURCES.txt" ] || die "no generated API surface in $GENERATED (Documentation~/unity-api-surface.md says how to generate it)"

unity_defines_for() {  # the UNITY_X_OR_NEWER symbols Unity defines for version $1
  local target="$1" defines="" version
  for version in 2022.2 2022.3 2023.1 2023.2 6000.0 6000.1 6000.2 6000.3 6000.4 6000.5 6000.6 6000.7; do
    defines="$defines;UNITY_${version/./_}_OR_NEWER"
    [ "$version" = "$target" ] && break
  done
  echo "-define:${defines#;}"
}

configure() {  # configure UNITY_VERSION INFERENCE(sentis-V|inference-engine-V|none)
  local unity="$1" inference="$2" name="unity$1-$2" dir="$OUT/unity$1-$2"
  mkdir -p "$dir"
  log "configuration $name"
  local unity_defines; unity_defines=$(unity_defines_for "$unity")
  local surface="$GENERATED/unity-$unity"

  build "$dir/UnityEngine.dll" "  surface UnityEngine ($unity, generated)" "$surface/UnityEngine.cs"
  build "$dir/UnityEditor.dll" "  surface UnityEditor ($unity, generated)" -r:"$dir/UnityEngine.dll" "$surface/UnityEditor.cs"
  build "$dir/UnityEngine.TestRunner.dll" "  surface UnityEngine.TestRunner" -r:"$dir/UnityEngine.dll" "${runner_stubs[@]}"
  local inference_ref=() inference_define=""
  case "$inference" in
    sentis-*)
      build "$dir/Unity.Sentis.dll" "  surface Unity.Sentis ${inference#sentis-} (generated)" -r:"$dir/UnityEngine.dll" "$GENERATED/$inference/Unity.Sentis.cs"
      inference_ref=(-r:"$dir/Unity.Sentis.dll"); inference_define=";LPNN_SENTIS" ;;
    inference-engine-*)
      build "$dir/Unity.InferenceEngine.dll" "  surface Unity.InferenceEngine ${inference#inference-engine-} (generated)" -r:"$dir/UnityEngine.dll" \
        "$GENERATED/$inference/Unity.InferenceEngine.cs"
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
  configurations=$((configurations + 1))
}

# The supported matrix (README "Supported matrix"): every Unity version with the inference package(s) it accepts.
configurations=0
configure 2022.3 sentis-2.1.3
configure 2022.3 none
configure 6000.0 sentis-2.1.3
configure 6000.0 inference-engine-2.2.2
configure 6000.0 inference-engine-2.4.0
configure 6000.3 inference-engine-2.3.0
configure 6000.3 inference-engine-2.4.0
configure 6000.5 inference-engine-2.2.2
configure 6000.7 inference-engine-2.2.2

log "compile-unity-layer: $compiled assemblies compiled in $configurations configurations against the generated surfaces ($GENERATED/SOURCES.txt); obsolete-member use is an error (-warnaserror); compilation only, nothing ran in Unity"

# The check can fail: a use of a member that Unity 6000.5 marks [Obsolete(..., true)] must be refused.
canary="$OUT/obsolete-canary.cs"
printf 'class ObsoleteCanary { int Id(UnityEngine.Object o) { return o.GetInstanceID(); } }\n' > "$canary"
if "${BASE[@]}" "${STRICT[@]}" -out:"$OUT/obsolete-canary.dll" -r:"$OUT/unity6000.5-inference-engine-2.2.2/UnityEngine.dll" "$canary" > "$OUT/obsolete-canary.log" 2>&1 \
   || ! grep -q "CS0619" "$OUT/obsolete-canary.log"; then
  die "the 6000.5 surface accepted Object.GetInstanceID() (expected error CS0619): the generated surface lost its [Obsolete] attributes"
fi
log "ok  Object.GetInstanceID() is refused against the 6000.5 surface (CS0619), as in Unity 6000.5"
