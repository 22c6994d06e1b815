#!/usr/bin/env bash
# The Python tests (pytest, tests/python/): the Python module against the binary,
# and FITS files read by astropy. Installs numpy, astropy and pytest from PyPI
# into a virtual environment under target/ (made once; python3-venv comes with apt
# where the system Python lacks venv), builds and installs the module the way a
# user does (`pip install ./python`: maturin, in the same target folder as the
# binary, so the traxer library is not compiled twice), and tests it against the
# release binary that `cargo test --release` built.
case "${1:-}" in -h | --help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 0 ;; esac
set -euo pipefail
cd "$(dirname "$0")/.."
venv=target/python-venv
if [ ! -x "$venv/bin/python" ]; then
  if ! python3 -m venv "$venv" 2>/dev/null; then
    rm -rf "$venv"
    SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
    echo "test-python: installing python3-venv with apt-get" >&2
    $SUDO apt-get install -y -qq --no-install-recommends python3-venv >/dev/null
    python3 -m venv "$venv"
  fi
fi
"$venv/bin/python" -m pip install -q --disable-pip-version-check -r tests/python/requirements.txt
# Cargo builds into CARGO_TARGET_DIR when it is set.
bin="$(cd "${CARGO_TARGET_DIR:-target}" 2>/dev/null && pwd)/release/traxer"
[ -x "$bin" ] || { cargo build --release; bin="$(cd "${CARGO_TARGET_DIR:-target}" && pwd)/release/traxer"; }
"$venv/bin/python" -m pip install -q --disable-pip-version-check --force-reinstall --no-deps ./python
TRAXER="$bin" "$venv/bin/python" -m pytest -q -rs tests/python "$@"
