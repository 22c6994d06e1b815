#!/usr/bin/env bash
# The combined mirror model (figure errors + roughness scatter) at PANTER: for each
# roughness level, the figure errors are fitted again to the PANTER Al Kα
# diameters alone (HPD 206″, 80 % 397″, 90 % 549″) with the roughness held fixed,
# and the fit predicts the Ti Kα and Fe Kα images with Monte Carlo and fit errors
# (`traxer fit-figure-error --predict`). Level 0 is today's model (figure errors
# only). The roughness is a fractal PSD P(f) = k f^-1.5 over 1e-3–1 µm⁻¹ (periods
# 1 µm – 1 mm), k set by its rms σ: σ² = ∫ P df = 61.25 k nm² (docs/telescope.md
# says why this band and what is assumed). σ = 0.5 nm is the preset
# slumped_glass_limit (data/roughness.toml), the published limit for this glass.
#
# Usage: scripts/roughness_study.sh [OUT_DIR] [SIGMA_NM...]
#   default OUT_DIR out/roughness_study, SIGMAS 0 0.5 1.0
# Writes OUT_DIR/sigma_S/ (each fit's files) and prints one table row per level.
# About 3 minutes per level on 2 cores (210 evaluations of 1 M photons).
case "${1:-}" in -h | --help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 0 ;; esac
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-out/roughness_study}
shift || true
sigmas=("$@")
[ ${#sigmas[@]} -gt 0 ] || sigmas=(0 0.5 1.0)
cargo build --release --quiet
T=target/release/traxer
mkdir -p "$out"
for s in "${sigmas[@]}"; do
  k=$(python3 -c "print(repr(float('$s')**2 / 61.25))")
  if python3 -c "import sys; sys.exit(0 if float('$s') > 0 else 1)"; then
    rough="{ psd = { type = \"power_law\", k = $k, n = 1.5 }, band_per_um = [1e-3, 1.0] }"
  else
    rough="none"
  fi
  "$T" fit-figure-error scenes/panter_al_ka.toml -q -D "roughness=$rough" \
    --target-hpd 206 --target-c80 397 --target-c90 549 --name "llnl_panter_sigma_${s//./p}" \
    --predict scenes/panter_ti_ka.toml --predict scenes/panter_fe_ka.toml \
    --out "$out/sigma_$s" > "$out/sigma_$s.log" 2>&1 || { cat "$out/sigma_$s.log" >&2; exit 1; }
  python3 - "$out/sigma_$s/fit.json" "$s" <<'PY'
import json, sys
fit, sigma = json.load(open(sys.argv[1])), sys.argv[2]
e = fit["parameter_errors"]
pars = ", ".join(f"{n} {v:.4g} ± {m:.2g} ± {f:.2g}" for n, v, m, f in
                 zip(e["names"], e["values"], e["monte_carlo"], e["fit"]))
sc = fit["seed_check"]
print(f"σ = {sigma} nm: {pars}")
print(f"  Al Kα (fitted): HPD {sc['hpd_mean_sd'][0]:.1f}″, 80 % {sc['d80_mean_sd'][0]:.1f}″, 90 % {sc['d90_mean_sd'][0]:.1f}″")
for p in fit["predictions"]:
    d, mc, ft = p["diameters"], p["monte_carlo"], p["fit"]
    line = "Ti Kα" if "ti_ka" in p["scene"] else "Fe Kα" if "fe_ka" in p["scene"] else p["scene"]
    print(f"  {line} (predicted): HPD {d['hpd']:.1f} ± {mc[0]:.1f} ± {ft[0]:.1f}″, "
          f"80 % {d['d80']:.1f} ± {mc[1]:.1f} ± {ft[1]:.1f}″, 90 % {d['d90']:.1f} ± {mc[2]:.1f} ± {ft[2]:.1f}″")
PY
done
