#!/usr/bin/env bash
# Fingerprints of every image the shipped scenes produce at a fixed seed: each
# scene in scenes/ is traced (seed 7, $PHOTONS photons, 2 threads) and each of its
# cameras rendered (160×100, 8 spp, seed 3; with the traced image on the sensors
# too); then the studies run at fixed seeds (effective area with its ARFs, PSF
# library, systematics, focus scan, figure-error fit, mesh comparison, solar
# flux: studies/ in the listing); prints the SHA-256 of
# every image and table written (.npy, .png, .csv, .arf, .fits; FITS with their DATE,
# CREATOR and EMBREE cards blanked), one per line, sorted. Provenance JSON is left out: it holds
# times and the command line.
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
st="$work/studies"
"$bin" effective-area scenes/llnl_effective_area.toml --energies 1:8:0.5 --angles 0,3,6 \
  -n "$((photons / 4))" -s 3 -j 2 -q --out "$st/effective_area" >/dev/null
"$bin" psf scenes/xmm_effective_area.toml --energies 1.5,6.4 --angles 0,5 --window 41 \
  -n "$((photons / 10))" -s 3 -j 2 -q --out "$st/psf" >/dev/null
"$bin" systematics scenes/panter_al_ka.toml --sources figure --figure-draws 3 \
  --vary sensor_z=-1539:-1499 -n "$((photons / 10))" -s 2 -j 2 -q --out "$st/systematics" >/dev/null
"$bin" focus scenes/panter_al_ka.toml --from -1534 --to -1504 --steps 4 \
  -n "$((photons / 10))" -s 2 -j 2 -q --out "$st/focus" >/dev/null
"$bin" fit-figure-error scenes/panter_al_ka.toml --target-hpd 206 --target-c80 397 \
  --target-c90 549 --global-evals 8 --local-evals 4 --check-seeds 1 \
  -n "$((photons / 20))" -s 2 -j 2 -q --out "$st/fit" >/dev/null
"$bin" compare scenes/panter_al_ka.toml --resolutions 8x1,30x1 \
  -n "$((photons / 10))" -s 2 -j 2 -q --out "$st/compare" >/dev/null
# compare.csv's last two columns are speeds and times: kept out of the fingerprint.
cut -d, -f1-11 "$st/compare/compare.csv" >"$st/compare/compare_without_times.csv"
rm "$st/compare/compare.csv"
"$bin" solar-flux --emission primakoff+abc -q --out "$st/solar" >/dev/null
cd "$work"
find . -type f \( -name '*.npy' -o -name '*.png' -o -name '*.csv' -o -name '*.arf' -o -name '*.fits' \) -print0 |
  sort -z | while IFS= read -r -d '' f; do
    case "$f" in
    *.fits | *.arf) # DATE, CREATOR and EMBREE say when, by which commit and Embree: blanked
      sum=$(perl -0777 -pe 's/(DATE    = |CREATOR = |EMBREE  = ).{70}/$1 . ("-" x 70)/ges' "$f" | sha256sum) ;;
    *) sum=$(sha256sum <"$f") ;;
    esac
    echo "${sum%% *}  $f"
  done
