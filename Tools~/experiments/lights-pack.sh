#!/usr/bin/env bash
# Proves `lpnn scene lights` on every level of the OpenArena maps pak (Documentation~/benchmarks.md "The light rig"):
# runs the command on each level and lists those it cannot do, with the command's own reason.
#   [PAK=FILE] bash Tools~/experiments/lights-pack.sh [SCHEME] [OUT_DIR]   (default: quick = one 20-iteration L-BFGS phase)
# Exit code 0 when every level with baked light succeeds; levels without baked light are listed, not failed.
source "$(dirname "$0")/../lib.sh"
cd "$REPO_ROOT"
PY=$(bash "Tools~/setup-python.sh")
export LPNN_OPENARENA_PAK
if [ -n "${PAK:-}" ]; then  # PAK=FILE: that pak's levels, nothing installed (the smoke test's synthetic pak)
  LPNN_OPENARENA_PAK=$PAK
else
  LPNN_OPENARENA_PAK=$(bash "Tools~/install-openarena.sh")
  bash "Tools~/install-openarena-textures.sh" >/dev/null  # shader scripts and textures of the forward model (lights.md §1)
fi
SCHEME="${1:-quick}"
OUT="${2:-$BUILD_DIR/lights-pack}"
mkdir -p "$OUT"
lpnn() { nice -n 10 "$REPO_ROOT/Tools~/bin/lpnn" "$@"; }
levels=$(PYTHONPATH="$TRAINING_DIR" "$PY" -c \
  "from lpnn.scenes.levels import default_pak, pak_members; print(' '.join(m[5:-4] for m in pak_members(default_pak())))")
done=0; unlit=(); failed=()
for level in $levels; do
  started=$SECONDS
  if line=$(lpnn scene lights "$level" --scheme "$SCHEME" --out "$OUT/$level.json" --quiet 2>"$OUT/$level.err" | tail -n 1); then
    done=$((done + 1))
    printf '%-16s %4d s  %s\n' "$level" $((SECONDS - started)) "${line#"$OUT/"}"
  else
    reason=$(tail -n 1 "$OUT/$level.err")
    if [[ "$reason" == *"no surface carries baked light"* ]]; then unlit+=("$level: $reason"); else failed+=("$level: $reason"); fi
    printf '%-16s %4d s  CANNOT: %s\n' "$level" $((SECONDS - started)) "$reason"
  fi
done
echo "$done levels recovered with scheme $SCHEME; ${#unlit[@]} without baked light; ${#failed[@]} failed"
for entry in "${unlit[@]}" "${failed[@]}"; do [ -n "$entry" ] && echo "  $entry"; done
[ "${#failed[@]}" -eq 0 ]
