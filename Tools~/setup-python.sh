#!/usr/bin/env bash
# Creates (or reuses) the Python environment for Training~ and prints its python executable.
# The venv lives outside the checkout, keyed by a hash of the pinned requirements, so clean
# clones and CI reuse it; project code is used through PYTHONPATH, never installed into it (a shared venv would
# otherwise run whichever checkout installed last): each checkout's Tools~/bin/lpnn runs that checkout's code.
source "$(dirname "$0")/lib.sh"
command -v python3.11 >/dev/null 2>&1 || command -v python3 >/dev/null 2>&1 || die "Python 3.11 is required"
PY=$(command -v python3.11 || command -v python3)
"$PY" -c 'import sys; sys.exit(0 if sys.version_info[:2] == (3, 11) else 1)' \
  || die "Python 3.11 is required, found $("$PY" --version 2>&1)"
lock="$TRAINING_DIR/requirements.lock"
hash=$(sha256sum "$lock" | cut -c1-12)
venv="${LPNN_VENV:-$LPNN_CACHE/venv-$hash}"
ready="$venv/.lpnn-ready"        # written last: the environment is complete
ours="$venv/.lpnn-created-here" # written first: this script made the folder, so it may remove a half-built one
if [ ! -f "$ready" ]; then
  # One creator at a time: `make demo` and `make test` started together must not both rebuild the same venv.
  mkdir -p "$LPNN_CACHE"
  if command -v flock >/dev/null 2>&1; then
    exec 9>"$LPNN_CACHE/setup-python.lock"
    flock -n 9 || { log "waiting for another setup of the Python environment to finish"; flock 9; }
  else
    log "no flock on this machine: do not start two setups of the Python environment at once"
  fi
  if [ ! -f "$ready" ]; then
    if [ -e "$venv" ] && [ ! -f "$ours" ]; then
      die "$venv exists but was not created by this script (no $(basename "$ready")); it is left untouched. \
Point LPNN_VENV at a new folder, or remove $venv yourself if it is a broken copy of ours"
    fi
    log "creating Python environment $venv (TensorFlow is ~1.7 GB; done once per requirements change)"
    rm -rf "$venv"  # only a half-built environment of ours reaches here
    mkdir -p "$venv"
    touch "$ours"
    "$PY" -m venv "$venv"
    "$venv/bin/python" -m pip install -q --disable-pip-version-check -r "$lock"
    touch "$ready"
  fi
fi
echo "$venv/bin/python"
