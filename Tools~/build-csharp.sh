#!/usr/bin/env bash
# Compiles the engine-agnostic core and its NUnit tests with Mono's mcs into Build~/.
source "$(dirname "$0")/lib.sh"
PKG="$REPO_ROOT/Packages/com.lpnn.probes"
NUNIT_DLL=/usr/lib/cli/nunit.framework-2.6.3/nunit.framework.dll
[ -f "$NUNIT_DLL" ] || die "NUnit 2.6 framework not found at $NUNIT_DLL (run Tools~/install-system.sh)"
mkdir -p "$BUILD_DIR"
MCS=(mcs -nologo -langversion:7.2 -debug -warn:4 -warnaserror+ -nowarn:1591
     -r:System.Numerics.dll -r:System.Numerics.Vectors.dll)

mapfile -t core_sources < <(find "$PKG/Runtime/Core" -name '*.cs' | sort)
"${MCS[@]}" -target:library -out:"$BUILD_DIR/Lpnn.Probes.Core.dll" "${core_sources[@]}"

mapfile -t test_sources < <(find "$REPO_ROOT/Tests/Core" -name '*.cs' | sort)
"${MCS[@]}" -target:library -out:"$BUILD_DIR/Lpnn.Probes.Core.Tests.dll" \
  -r:"$BUILD_DIR/Lpnn.Probes.Core.dll" -r:"$NUNIT_DLL" "${test_sources[@]}"
cp "$NUNIT_DLL" "$BUILD_DIR/"
log "built Build~/Lpnn.Probes.Core.dll and Build~/Lpnn.Probes.Core.Tests.dll"
