#!/usr/bin/env bash
# Pushes the synthetic truth's prepared beds (layer-by-height:h_fraction=0.5, mu_r=0.2, seeds 1-3,
# from the store of the scan in README.md) again at other rolling frictions: the bed stays the
# same, only the push changes. Prints one line per run: seed, mu_r, peak, maximum contact force,
# mean force (N), from each push's push_summary.toml.
#   results/calibration/synthetic_truth_mini/push_only.sh STORE OUT
set -euo pipefail
store=${1:?the store of the scan (its runs/ folder holds the truth runs)}
out=${2:?a folder for the pushes}
mfdem=${MFDEM:-build/studies/mfdem}
printf "%4s %6s %9s %12s %9s\n" seed mu_r peak_N max_contact_N mean_F_N
for seed in 1 2 3; do
  bed=$(ls -d "$store"/runs/s${seed}-layer-by-height_h_fraction_0.5_mu_r_0.2-*/ | head -1)
  for mu_r in 0 0.1 0.19 0.195 0.2 0.205 0.21 0.3 0.4 0.6; do
    dir="$out/s$seed/mu_r_$mu_r"
    [ -f "$dir/push_summary.toml" ] || "$mfdem" push "$bed/packing.h5" --rolling-friction "$mu_r" --threads 1 -q --out "$dir"
    value() { sed -n "s/^$1 = //p" "$dir/push_summary.toml"; }
    printf "%4s %6s %9.2f %12.2f %9.2f\n" "$seed" "$mu_r" "$(value peak_force)" "$(value max_contact_force)" "$(value mean_force)"
  done
done
