#!/usr/bin/env bash
# Regenerates the meshes shipped in meshes/ from their analytic definitions.
case "${1:-}" in -h | --help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 0 ;; esac
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --quiet
T=target/release/traxer
$T tessellate meshes/parts.toml --object entrance_aperture --out meshes/entrance_aperture.gltf
$T tessellate meshes/parts.toml --object central_blocker --out meshes/central_blocker.obj
# The CAST LLNL telescope: one file, one named part per mirror, glass back and
# edge (104 parts). 60 × 2 is 0.5° per segment: its HPD matches the analytic
# telescope to 0.1 % (README, "Analytic vs meshed telescope").
for f in glb obj; do
  $T tessellate meshes/llnl_telescope.toml --segments 60 --rings 2 --out meshes/llnl_telescope.$f
done
# The magnet bore and the sensor plate, in their own frames.
$T tessellate meshes/cast_parts.toml --out meshes/ --format gltf,obj
