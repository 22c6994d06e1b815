#!/usr/bin/env bash
# Regenerates the pictures in docs/img/ that the README shows.
case "${1:-}" in -h | --help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 0 ;; esac
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --quiet
T=target/release/traxer
tmp=$(mktemp -d)
$T trace scenes/wolter1_parallel.toml -n 2000000 -D focus_shift=60 -D off_axis=0.05 --out "$tmp" -q
cp "$tmp/sensor_log.png" docs/img/wolter1_defocus_log.png
$T reflectivity --coating llnl_recipe_3 --energy 1.49,4.51,6.41 --angle 0:3:0.005 \
  --plot docs/img/llnl_recipe_3_reflectivity.png > /dev/null
$T focus scenes/panter_al_ka.toml -D figure_error=none --from=-1460 --to=-1580 --steps 13 --out "$tmp/focus" -q
cp "$tmp/focus/focus.png" docs/img/panter_al_ka_focus.png
rm -rf "$tmp"
# PANTER Al/Ti/Fe Kα: perfect figure vs the fitted figure errors, and all EEFs.
cargo run --release --quiet --example panter_pictures
# Visible-light renders: the classic spheres, and the LLNL telescope with the
# PANTER Al Kα image glowing on its sensor.
$T render scenes/spheres.toml --width 600 --height 400 --spp 64 --out docs/img/spheres.png
tmp=$(mktemp -d)
$T trace scenes/panter_al_ka.toml -n 2000000 --out "$tmp" -q
$T render scenes/panter_al_ka.toml --camera telescope --width 480 --height 300 --spp 64 \
  --sensor-image "$tmp" --log-decades 3 --out docs/img/llnl_telescope_view.png
$T render scenes/panter_al_ka.toml --camera sensor --width 480 --height 300 --spp 16 \
  --sensor-image "$tmp" --log-decades 3 --out docs/img/llnl_sensor_view.png
rm -rf "$tmp"
# The solar axion image at CAST (10 million photons, as the README's numbers; in
# X-rays per second, the magnet on as the scene has it) and the overview: the chip glowing with it, the telescope, the bore and the Sun.
tmp=$(mktemp -d)
$T trace scenes/cast_axion_image.toml -n 10000000 --out "$tmp" -q
cp "$tmp/chip.png" docs/img/cast_axion_image.png
cp "$tmp/chip_log.png" docs/img/cast_axion_image_log.png
cp "$tmp/chip_grid.png" docs/img/cast_axion_image_grid.png
$T render scenes/cast_axion_image.toml --camera overview --width 720 --height 450 --spp 64 --labels \
  --sensor-image "$tmp" --log-decades 3 --out docs/img/cast_overview.png
rm -rf "$tmp"
# The axion–electron image (ABC + Primakoff) and where its X-rays convert.
tmp=$(mktemp -d)
$T trace scenes/cast_axion_electron_image.toml -n 10000000 --out "$tmp" -q
cp "$tmp/chip.png" docs/img/cast_axion_electron_image.png
cp "$tmp/chip_log.png" docs/img/cast_axion_electron_image_log.png
cp "$tmp/chip_conversion_depth.png" docs/img/cast_axion_electron_conversion_depth.png
rm -rf "$tmp"
# The LLNL telescope's effective area, vignetting and off-axis image quality.
tmp=$(mktemp -d)
$T effective-area scenes/llnl_effective_area.toml --energies 1:10:0.1 --angles 0:10:2.5 --out "$tmp" -q
cp "$tmp/effective_area.png" docs/img/llnl_effective_area.png
cp "$tmp/vignetting.png" docs/img/llnl_vignetting.png
cp "$tmp/off_axis.png" docs/img/llnl_off_axis.png
rm -rf "$tmp"
# The XMM-Newton module's effective area, vignetting and off-axis image quality
# (perfect figure), and BabyIAXO's solar axion image (ABC + Primakoff, 10 million
# photons, converted in the magnet's field map, as the README's numbers).
tmp=$(mktemp -d)
$T effective-area scenes/xmm_effective_area.toml --energies 0.5:10:0.25 --angles 0:20:5 -n 1000000 --out "$tmp" -q
cp "$tmp/effective_area.png" docs/img/xmm_effective_area.png
cp "$tmp/vignetting.png" docs/img/xmm_vignetting.png
cp "$tmp/off_axis.png" docs/img/xmm_off_axis.png
rm -rf "$tmp"
tmp=$(mktemp -d)
$T trace scenes/babyiaxo_axion_image.toml -n 10000000 --out "$tmp" -q
cp "$tmp/detector.png" docs/img/babyiaxo_axion_image.png
cp "$tmp/detector_log.png" docs/img/babyiaxo_axion_image_log.png
rm -rf "$tmp"
# The live window (traxer view) on the CAST scene, under a virtual X server:
# the frame it saves is the window's picture.
tmp=$(mktemp -d)
xvfb-run -a -s "-screen 0 1024x768x24" $T view scenes/cast_axion_image.toml --camera overview \
  --width 800 --height 500 --photons 3000000 --log-decades 3 --frames 64 --save "$tmp"
cp "$tmp/frame.png" docs/img/view_cast.png
rm -rf "$tmp"
# The renders' provenance files are not shown in the README.
rm -f docs/img/*.json
