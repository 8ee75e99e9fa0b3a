#!/usr/bin/env bash
# Regenerate every figure shown in docs/figures.md into docs/figures/, and
# the gallery part of docs/figures.md (each figure with its caption).
#
#   scripts/figures.sh                      # the presets as they are
#   scripts/figures.sh --nodes 64 --steps 200   # a quicker, coarser grid
#
# Extra arguments go to every `shakedown figure` call. The data are kept
# beside the figures (NAME.csv), so a restyle is a redraw:
#
#   REDRAW=1 scripts/figures.sh --nodes 64 --steps 200   # from docs/figures/NAME.csv, nothing run
#
# Every figure checked in under docs/ is made by this script. The docs
# show the SVGs (small, text as text); the PNGs `figure` also writes (600
# dpi, about 1 MB each) are not kept here.
set -euo pipefail
cd "$(dirname "$0")/.."
out=docs/figures
mkdir -p "$out"
cargo build --release --quiet
bin=target/release/shakedown
names=(fig3 fig4 fig5 fig6 fig7 fig8 fig9 regime design)
for name in "${names[@]}"; do
    if [[ "${REDRAW:-0}" == 1 ]]; then
        "$bin" figure "$name" --from "$out/$name.csv" --out "$out" --force "$@"
    else
        "$bin" figure "$name" --out "$out" --force "$@"
    fi
done
# The slide version of Fig. 3, to show what --style slide --title gives.
"$bin" figure fig3 --from "$out/fig3.csv" --out "$out/slide" --style slide --title --force "$@"
rm -f "$out"/*.png "$out"/slide/*.png

# The gallery: everything after the marker line of docs/figures.md.
page=docs/figures.md
marker='<!-- gallery: made by scripts/figures.sh, do not edit below -->'
{
    awk -v m="$marker" '{ print } $0 == m { exit }' "$page"
    for name in "${names[@]}"; do
        printf '\n## %s\n\n`shakedown figure %s --out DIR`\n\n' "$name" "$name"
        printf '![%s](figures/%s.svg)\n\n> %s\n' "$name" "$name" "$(cat "$out/$name.caption.txt")"
    done
    printf '\n## A slide\n\n`shakedown figure fig3 --from docs/figures/fig3.csv --out DIR --style slide --title`\n\n'
    printf '![fig3 as a slide](figures/slide/fig3.svg)\n'
} > "$page.new"
mv "$page.new" "$page"
