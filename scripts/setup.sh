#!/usr/bin/env bash
# Installs what traxer needs to build, if it is missing: Intel Embree (3.13 or 4.x),
# libclang (for bindgen) and CMake (for NLopt), from the system's packages. Safe to run repeatedly.
# Set EMBREE_DIR to use an Embree of your own instead.
case "${1:-}" in -h | --help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 0 ;; esac
set -euo pipefail
cd "$(dirname "$0")/.."

have_embree() {
  [ -n "${EMBREE_DIR:-}" ] && return 0
  [ -n "${EMBREE_INCLUDE_DIR:-}" ] && return 0
  for d in /usr/include /usr/local/include /opt/homebrew/include; do
    if [ -f "$d/embree4/rtcore.h" ] || [ -f "$d/embree3/rtcore.h" ]; then return 0; fi
  done
  return 1
}

have_libclang() {
  [ -n "${LIBCLANG_PATH:-}" ] && return 0
  # bindgen needs libclang and clang's own headers (stddef.h): on Debian/Ubuntu
  # both come with libclang-dev.
  if command -v dpkg-query >/dev/null 2>&1; then
    dpkg-query -W -f='${Status}' libclang-dev 2>/dev/null | grep -q "install ok installed"
    return
  fi
  ldconfig -p 2>/dev/null | grep -q 'libclang[-.0-9]*\.so'
}

missing=()
have_embree || missing+=(libembree-dev)
have_libclang || missing+=(libclang-dev)
command -v cc >/dev/null 2>&1 || missing+=(build-essential)
# The nlopt crate (figure-error fit) builds NLopt's C sources with CMake.
command -v cmake >/dev/null 2>&1 || missing+=(cmake)
# The live window's tests run `traxer view` under a virtual X server, with
# synthetic keys and mouse (xdotool).
command -v Xvfb >/dev/null 2>&1 || missing+=(xvfb)
command -v xdotool >/dev/null 2>&1 || missing+=(xdotool)

if [ ${#missing[@]} -gt 0 ]; then
  if ! command -v apt-get >/dev/null 2>&1; then
    echo "traxer needs: ${missing[*]} (Embree 3.13+/4.x, libclang). Install them with your" >&2
    echo "package manager, or set EMBREE_DIR to an Embree installation." >&2
    exit 1
  fi
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
  echo "setup: installing ${missing[*]} with apt-get" >&2
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

if ! command -v cargo >/dev/null 2>&1 || ! command -v rustc >/dev/null 2>&1; then
  echo "traxer needs Rust (cargo and rustc): install it with rustup, the official Rust installer." >&2
  exit 1
fi

# The oldest Rust that builds traxer and its locked dependencies (Cargo.toml's
# rust-version). Distributions ship older ones (Debian 13: 1.85, Ubuntu 24.04: 1.75).
need=$(sed -n 's/^rust-version = "\([0-9.]*\)"/\1/p' Cargo.toml)
have=$(rustc --version | sed -n 's/^rustc \([0-9][0-9.]*\).*/\1/p')
older() { # whether version $1 is older than $2 (major.minor[.patch])
  [ "$(printf '%s\n%s\n' "$1" "$2" | sort -V | head -n 1)" = "$1" ] && [ "$1" != "$2" ]
}
if [ -z "$have" ] || older "$have" "$need"; then
  echo "traxer needs Rust $need or newer; this rustc is ${have:-unknown} ($(command -v rustc))." >&2
  echo "Install a current Rust with rustup (the official installer), or run \`rustup update stable\`" >&2
  echo "if you have it; a distribution's rustc package is usually too old." >&2
  exit 1
fi
