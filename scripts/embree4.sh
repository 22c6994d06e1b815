#!/usr/bin/env bash
# Builds traxer against Embree 4 on a Debian 12 machine (whose own package is
# Embree 3), runs the test suite with it, and checks that every shipped scene's
# images are bit-identical to the Embree 3 build's (scripts/output_hashes.sh).
#
# Embree 4 comes, without installing anything system-wide (ARCHITECTURE.md):
#   - the headers from Debian 13's libembree-dev, fetched with apt from the
#     archive this system already uses (a temporary sources list: the system's
#     own, with the suite changed to trixie), unpacked with dpkg-deb;
#   - the library from the PyPI wheel embreex (embreex.libs/ holds libembree4
#     and libtbb), renamed to the soname libembree4.so.4 with patchelf.
# Both are cached in $TRAXER_EMBREE4_CACHE (default ~/.cache/traxer-embree4).
# Run by .ci/run after the main tests; usable by hand:  scripts/embree4.sh
case "${1:-}" in -h | --help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 0 ;; esac
set -euo pipefail
cd "$(dirname "$0")/.."

cache=${TRAXER_EMBREE4_CACHE:-$HOME/.cache/traxer-embree4}
root=$cache/root

fetch() {
  local work
  work=$(mktemp -d)
  trap 'rm -rf "$work"' RETURN
  # A sources list for Debian 13 from the system's own (deb822 or one-line form).
  local list=$work/trixie.sources
  if [ -f /etc/apt/sources.list.d/debian.sources ]; then
    awk 'BEGIN { RS = ""; ORS = "\n\n" } /Suites:/ && !/security/ {
           sub(/Suites:[^\n]*/, "Suites: trixie"); print; exit }' \
      /etc/apt/sources.list.d/debian.sources > "$list"
  elif [ -f /etc/apt/sources.list ]; then
    list=$work/trixie.list
    awk '$1 == "deb" && $0 !~ /security/ { $3 = "trixie"; print; exit }' /etc/apt/sources.list > "$list"
  fi
  if [ ! -s "$list" ]; then
    echo "embree4: no Debian package source found in /etc/apt; this recipe is for Debian" >&2
    exit 1
  fi
  local apt=(-o "Dir::Etc::SourceList=$list" -o Dir::Etc::SourceParts=/dev/null
             -o "Dir::State::Lists=$work/lists" -o "Dir::Cache=$work/cache"
             -o Debug::NoLocking=1)
  mkdir -p "$work/lists/partial" "$work/cache/archives/partial"
  apt-get "${apt[@]}" update -qq
  (cd "$work" && apt-get "${apt[@]}" download -qq libembree-dev 2>/dev/null)
  dpkg-deb -x "$work"/libembree-dev_*.deb "$work/deb"
  python3 -m pip download -q --no-deps --only-binary=:all: embreex -d "$work/wheel"
  python3 -m zipfile -e "$work"/wheel/embreex-*.whl "$work/whl"
  command -v patchelf >/dev/null 2>&1 || {
    SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
    $SUDO apt-get install -y -qq --no-install-recommends patchelf >/dev/null
  }
  rm -rf "$root" && mkdir -p "$root/include" "$root/lib"
  cp -r "$work/deb/usr/include/embree4" "$root/include/"
  cp "$work"/whl/embreex.libs/libembree4-*.so.4 "$root/lib/libembree4.so.4"
  cp "$work"/whl/embreex.libs/libtbb-*.so.* "$root/lib/"
  patchelf --set-soname libembree4.so.4 "$root/lib/libembree4.so.4"
  ln -sf libembree4.so.4 "$root/lib/libembree4.so"
}

start=$(date +%s)
if [ ! -f "$root/lib/libembree4.so.4" ] || [ ! -f "$root/include/embree4/rtcore.h" ]; then
  echo "embree4: fetching Embree 4 headers and library into $cache" >&2
  fetch
fi

# The Embree 3 binary for the image comparison, before the build switches.
cargo build --release --quiet
e3=$(mktemp -d)
trap 'rm -rf "$e3"' EXIT
cp target/release/traxer "$e3/traxer"

export EMBREE_DIR=$root LD_LIBRARY_PATH=$root/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
# The tests' reflectivity tables (about 6 GB) stay cached through the run.
TRAXER_CACHE_MAX_MB="${TRAXER_CACHE_MAX_MB:-100000}" cargo test --release
version=$(target/release/traxer info | sed -n 's/^Embree \([0-9.]*\).*/\1/p')
case "$version" in
  4.*) ;;
  *) echo "embree4: the build links Embree $version, not 4" >&2; exit 1 ;;
esac
scripts/output_hashes.sh "$e3/traxer" > "$e3/e3.txt"
scripts/output_hashes.sh target/release/traxer > "$e3/e4.txt"
if ! diff "$e3/e3.txt" "$e3/e4.txt" >&2; then
  echo "embree4: images differ between Embree 3 and Embree $version" >&2
  exit 1
fi
echo "embree4: Embree $version: tests pass, $(wc -l < "$e3/e4.txt") images bit-identical to Embree 3 ($(($(date +%s) - start)) s)" >&2
