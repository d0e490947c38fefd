#!/usr/bin/env bash
# Create the project's virtual environment with the pinned packages (pyproject.toml).
# On Debian, `python3 -m venv` needs python3-venv: installed when run as root,
# otherwise named in the error.
set -euo pipefail
python=${1:-python3}
venv=${2:-.venv}

if ! "$python" -c 'import ensurepip, venv' 2>/dev/null; then
    if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
        echo "[setup] installing python3-venv"
        apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq python3-venv
    else
        echo "error: $python cannot create a virtual environment; install python3-venv (sudo apt-get install -y python3-venv)" >&2
        exit 1
    fi
fi
if [ ! -x "$venv/bin/python" ]; then
    echo "[setup] creating $venv"
    "$python" -m venv "$venv"
fi
echo "[setup] installing the project and its pinned packages into $venv"
"$venv/bin/python" -m pip install -q --disable-pip-version-check -e '.[dev]'
