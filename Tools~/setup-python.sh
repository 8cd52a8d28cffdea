#!/usr/bin/env bash
# Creates (or reuses) the Python environment for Training~ and prints its python executable.
# The venv lives outside the checkout, keyed by a hash of the pinned requirements, so clean
# clones and CI reuse it; project code is used through PYTHONPATH, never installed into it.
source "$(dirname "$0")/lib.sh"
command -v python3.11 >/dev/null 2>&1 || command -v python3 >/dev/null 2>&1 || die "Python 3.11 is required"
PY=$(command -v python3.11 || command -v python3)
"$PY" -c 'import sys; sys.exit(0 if sys.version_info[:2] == (3, 11) else 1)' \
  || die "Python 3.11 is required, found $("$PY" --version 2>&1)"
lock="$TRAINING_DIR/requirements.lock"
hash=$(sha256sum "$lock" | cut -c1-12)
venv="${LPNN_VENV:-$LPNN_CACHE/venv-$hash}"
if [ ! -f "$venv/.lpnn-ready" ]; then
  log "creating Python environment $venv (TensorFlow is ~1.7 GB; done once per requirements change)"
  rm -rf "$venv"
  mkdir -p "$(dirname "$venv")"
  "$PY" -m venv "$venv"
  "$venv/bin/python" -m pip install -q --disable-pip-version-check -r "$lock"
  touch "$venv/.lpnn-ready"
fi
echo "$venv/bin/python"
