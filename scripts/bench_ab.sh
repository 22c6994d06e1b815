#!/bin/bash
# Before/after speed comparison: `traxer bench` on every row of `cargo bench`'s
# photon table with each given binary in turn, alternating, for ROUNDS rounds, so
# that both see the same machine load. Prints one line per scene and binary:
# photons/s, reaching the sensor per second, queries per photon, raw rtcIntersect1
# rays/s, share inside Embree.
#
# Usage: scripts/bench_ab.sh OLD_TRAXER NEW_TRAXER [PHOTONS] [ROUNDS]
# (build the old binary from an earlier commit with its own CARGO_TARGET_DIR).
# Environment: ROWS=REGEX keeps only the rows whose scene matches it; NEW_DEFINE
# adds one more -D NAME=VALUE to the new side only, so one binary can be compared
# with itself and a scene variable, e.g. the roughness scatter on the PANTER rows:
#   ROWS=panter NEW_DEFINE='roughness={ psd = ... }' scripts/bench_ab.sh T T
case "${1:-}" in -h | --help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 0 ;; esac
set -euo pipefail
cd "$(dirname "$0")/.."
[ $# -ge 2 ] || { echo "usage: $0 OLD_TRAXER NEW_TRAXER [PHOTONS] [ROUNDS]" >&2; exit 2; }
old=$1 new=$2 photons=${3:-2000000} rounds=${4:-2}
rows="wolter1_parallel.toml|coating=perfect
wolter1_parallel.toml|coating=llnl_recipe_3
wolter1_meshed.toml|coating=perfect
wolter1_meshed.toml|coating=llnl_recipe_3
panter_al_ka.toml|coating=perfect figure_error=none
panter_al_ka.toml|coating=as_built figure_error=llnl_panter
panter_al_ka_meshed.toml|coating=perfect figure_error=none
panter_al_ka_meshed.toml|coating=as_built figure_error=llnl_panter
cast_axion_image.toml|
llnl_effective_area.toml|"
printf '%-5s %-26s %-42s %10s %10s %7s %10s %6s\n' which scene variables "photons/s" "sensor/s" queries "raw/s" share
for round in $(seq "$rounds"); do
  while IFS='|' read -r scene defines; do
    [[ "$scene" =~ ${ROWS:-.} ]] || continue
    args=()
    for d in $defines; do args+=(-D "$d"); done
    for which in old new; do
      bin=$old; extra=()
      if [ "$which" = new ]; then
        bin=$new
        [ -n "${NEW_DEFINE:-}" ] && extra=(-D "$NEW_DEFINE")
      fi
      json=$("$bin" bench "scenes/$scene" "${args[@]}" "${extra[@]}" -n "$photons" -q --json)
      python3 - "$which" "$scene" "$defines" "$json" <<'PY'
import json, sys
which, scene, defines, text = sys.argv[1:]
r = json.loads(text)
print('%-5s %-26s %-42s %9.3fM %9.3fM %7.3f %9.2fM %6.2f' % (
    which, scene, defines, r['photons_per_second'] / 1e6,
    r['sensor_photons_per_second'] / 1e6, r['queries_per_photon'],
    r['raw_rays_per_second'] / 1e6, r['embree_fraction']))
PY
    done
  done <<< "$rows"
done
