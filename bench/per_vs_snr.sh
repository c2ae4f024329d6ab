#!/usr/bin/env bash
# PER-versus-SNR characterization of every PHY (CSV, PNG, table of the SNR at
# 10% and 1% PER). FRAMES per point (default 500) trades time for precision.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh release
OUT=out/per
mkdir -p "$OUT"
build/release/bench/rfsitl_per_sweep --frames "${FRAMES:-500}" --from -2 --to 30 --step 0.5 \
  --csv "$OUT/per_vs_snr.csv" "$@"
/usr/bin/python3 bench/plot_per.py "$OUT/per_vs_snr.csv" -o "$OUT/per_vs_snr.png" | tee "$OUT/table.md"
