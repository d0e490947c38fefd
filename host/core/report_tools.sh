#!/usr/bin/env bash
# Debian tools the report's tests use: chromium (a headless browser opens the HTML report)
# and gtkwave (its vcd2fst and fst2vcd read the VCD traces back). Installed when run as
# root; otherwise named. Not an error here: without them the tests that need them fail
# and say which package to install.
set -uo pipefail
missing=()
command -v chromium >/dev/null || missing+=(chromium)
command -v vcd2fst >/dev/null || missing+=(gtkwave)
[ ${#missing[@]} -eq 0 ] && exit 0
packages=("${missing[@]}" fonts-dejavu-core)
if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
    echo "[setup] installing ${packages[*]}"
    if apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${packages[@]}" >/dev/null; then
        exit 0
    fi
    echo "warning: could not install ${packages[*]}; the report's browser and VCD tests will fail" >&2
else
    echo "note: the report's tests need Debian's ${missing[*]}: sudo apt-get install -y ${packages[*]}" >&2
fi
