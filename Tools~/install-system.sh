#!/usr/bin/env bash
# Debian packages the C# build and tests need (idempotent).
source "$(dirname "$0")/lib.sh"
apt_install mono-devel nunit-console
