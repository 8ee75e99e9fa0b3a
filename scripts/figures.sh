#!/usr/bin/env bash
# Regenerate every figure shown in docs/figures.md into docs/figures/.
#
#   scripts/figures.sh                      # the presets as they are
#   scripts/figures.sh --nodes 64 --steps 200   # a quicker, coarser grid
#
# Extra arguments go to every `shakedown figure` call. The data are kept
# beside the figures (NAME.csv), so a restyle is a redraw:
#
#   REDRAW=1 scripts/figures.sh             # from docs/figures/NAME.csv, nothing run
#
# Every figure checked in under docs/ is made by this script.
set -euo pipefail
cd "$(dirname "$0")/.."
out=docs/figures
mkdir -p "$out"
cargo build --release --quiet
bin=target/release/shakedown
for name in fig3 fig4 fig5 fig6 fig7 fig8 fig9 regime; do
    if [[ "${REDRAW:-0}" == 1 ]]; then
        "$bin" figure "$name" --from "$out/$name.csv" --out "$out" "$@"
    else
        "$bin" figure "$name" --out "$out" --force "$@"
    fi
done
# The slide version of Fig. 3, to show what --style slide --title gives.
"$bin" figure fig3 --from "$out/fig3.csv" --out "$out/slide" --style slide --title "$@"
