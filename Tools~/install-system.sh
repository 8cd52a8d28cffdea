#!/usr/bin/env bash
# Debian packages the C# build and tests need (idempotent); Json.NET for the smoke test of
# Tools~/experiments/json-comparison/run.sh.
source "$(dirname "$0")/lib.sh"
apt_install mono-devel nunit-console libnewtonsoft-json-cil-dev
