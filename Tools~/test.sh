#!/usr/bin/env bash
# The README's test command: installs what is missing, builds and runs every test suite
# (C# core via Mono/NUnit, the Unity-layer compile check, the Python trainer via pytest),
# and ends with one line `N passed, N failed`. Exit code is non-zero on any failure.
source "$(dirname "$0")/lib.sh"
cd "$REPO_ROOT"
rm -rf "$BUILD_DIR/reports"; mkdir -p "$BUILD_DIR/reports"
checks="$BUILD_DIR/reports/checks.txt"; : > "$checks"
reports=()

step() {  # step NAME COMMAND... : records pass/fail of a non-runner step (callers add `|| true` to keep going)
  local name="$1"; shift
  if "$@"; then echo "pass $name" >> "$checks"; return 0; fi
  echo "fail $name" >> "$checks"; return 1
}

step "install system packages" bash "Tools~/install-system.sh" || true

if step "build C# core and tests (mcs)" bash "Tools~/build-csharp.sh"; then
  reports+=("$BUILD_DIR/reports/nunit-core.xml")
  (cd "$BUILD_DIR" && nunit-console -nologo -labels -exclude=RealLevelRehearsal Lpnn.Probes.Core.Tests.dll \
      -xml="$BUILD_DIR/reports/nunit-core.xml" > "$BUILD_DIR/reports/nunit-core.log" 2>&1) || true
  tail -n 15 "$BUILD_DIR/reports/nunit-core.log" | grep -E "Tests run|Errors and Failures|^[0-9]+\)" || true
fi

step "compile Runtime, Editor, Tests/Editor and the sample against the declared Unity API surface" \
  bash "Tools~/compile-unity-layer.sh" || true
step "public API is Documentation~/public-api.txt (internal by default)" bash "Tools~/check-public-api.sh" || true
step "package layout: .meta files, asmdefs, package.json" python3 "Tools~/check-package.py" || true

if PY=$(bash "Tools~/setup-python.sh"); then
  echo "pass set up Python environment" >> "$checks"
  step "lint Python (ruff: ordinary checks, and the package's layers in Tools~/lint-python.py)" \
    "$PY" "Tools~/lint-python.py" || true
  export LPNN_OPENARENA_PAK
  LPNN_OPENARENA_PAK=$(bash "Tools~/install-openarena.sh") || echo "fail install openarena-081-maps" >> "$checks"
  reports+=("$BUILD_DIR/reports/pytest.xml")
  PYTHONPATH="$TRAINING_DIR" "$PY" -m pytest "$TRAINING_DIR/tests" -p no:cacheprovider \
      --junitxml="$BUILD_DIR/reports/pytest.xml" -q -o junit_family=xunit2 || true
else
  echo "fail set up Python environment" >> "$checks"
fi

python3 "Tools~/summarize.py" "$checks" "${reports[@]}"
