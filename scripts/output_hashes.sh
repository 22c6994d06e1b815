#!/usr/bin/env bash
# Fingerprints of every image the shipped scenes produce at a fixed seed: each
# scene in scenes/ is traced (seed 7, $PHOTONS photons, 2 threads) and each of its
# cameras rendered (160×100, 8 spp, seed 3; with the traced image on the sensors
# too); prints the SHA-256 of every image
# and table written (.npy, .png, .csv), one per line, sorted. Provenance JSON is
# left out: it holds times and the command line.
#
# Used to check that a change which must not alter results does not:
#   scripts/output_hashes.sh ./before-binary > before.txt
#   scripts/output_hashes.sh target/release/traxer > after.txt
#   diff before.txt after.txt
case "${1:-}" in -h | --help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 0 ;; esac
set -euo pipefail
bin=$(realpath "${1:?usage: output_hashes.sh TRAXER_BINARY}")
photons=${PHOTONS:-200000}
cd "$(dirname "$0")/.."
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for scene in scenes/*.toml; do
  name=$(basename "$scene" .toml)
  if grep -q '^\[\[sources\]\]' "$scene"; then
    "$bin" trace "$scene" -n "$photons" -s 7 -j 2 -q --out "$work/$name" >/dev/null
  fi
  for camera in $(sed -n 's/^\[cameras\.\([A-Za-z0-9_-]*\)\].*/\1/p' "$scene"); do
    "$bin" render "$scene" --camera "$camera" --width 160 --height 100 --spp 8 \
      -s 3 -j 2 --out "$work/$name-render-$camera.png" >/dev/null
    if [ -d "$work/$name" ]; then # the X-ray image glowing on the sensor
      "$bin" render "$scene" --camera "$camera" --width 160 --height 100 --spp 8 \
        -s 3 -j 2 --sensor-image "$work/$name" --log-decades 3 \
        --out "$work/$name-render-$camera-glow.png" >/dev/null
    fi
  done
done
cd "$work"
find . -type f \( -name '*.npy' -o -name '*.png' -o -name '*.csv' \) -print0 |
  sort -z | xargs -0 sha256sum
