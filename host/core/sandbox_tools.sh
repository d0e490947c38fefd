#!/usr/bin/env bash
# Debian's bubblewrap: the firmware's interpreter runs in namespaces of its own through it
# (host/rig/targets/sandbox.py, docs/security.md). Installed when run as root; otherwise named.
# Not an error here: without it a run says so once and goes on with the shim's confinement.
set -uo pipefail
command -v bwrap >/dev/null && exit 0
if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
    echo "[setup] installing bubblewrap"
    if apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends bubblewrap >/dev/null; then
        exit 0
    fi
    echo "warning: could not install bubblewrap; the firmware runs without its sandbox (docs/security.md)" >&2
else
    echo "note: the firmware's sandbox needs Debian's bubblewrap: sudo apt-get install -y bubblewrap" >&2
fi
