#!/usr/bin/env bash
# plot_trade.sh - plots bench_trade's summary: median frame time (log x) against median relative L2 error,
# one curve per mode family, the Pareto front dashed; one PNG per image size (gnuplot, package gnuplot-nox).
# usage: plot_trade.sh SUMMARY.tsv OUT_PREFIX [path|path-top]   (writes OUT_PREFIX_SIZE.png for each size in the
# summary; "path": SUMMARY is bench_trade --path's OUT_PREFIX_path_summary.tsv, the error against method "path" with
# the walks' noise cancelled; "path-top": path_summary_top.py's, with the cases the walks cannot resolve at the top
# of their interval)
set -euo pipefail
tsv=$1 prefix=$2 against=${3:-reference}
if [[ $against == path ]]; then
    truth="method 'path' (error without the walks' noise)"
elif [[ $against == path-top ]]; then
    truth="'path', w/o its noise, unresolved cases at their interval's top"
else
    truth="method 'reference'"
fi
command -v gnuplot >/dev/null || { echo "plot_trade.sh: gnuplot not found (apt-get install gnuplot-nox)" >&2; exit 1; }
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT

rows() {  # rows SIZE REGEX: that size's modes whose name matches, fastest first
    awk -F'\t' -v size="$1" -v re="$2" 'NR > 1 && $1 == size && $2 ~ re' "$tsv" | sort -t$'\t' -g -k3
}

plot_size() {  # plot_size SIZE
    local size=$1 out="${prefix}_$1.png"
    rows "$size" '^single' > "$dir/single.tsv"
    rows "$size" '^five( samples [0-9]+)?$' > "$dir/samples.tsv"
    rows "$size" '^five( projection [0-9]+)?$' > "$dir/projection.tsv"
    rows "$size" 'per_channel' > "$dir/per_channel.tsv"
    rows "$size" '(better_dipole|burley|asymptotic_dipole)$' > "$dir/profiles.tsv"
    rows "$size" '^auto' > "$dir/auto.tsv"
    rows "$size" '' | awk -F'\t' '$6 == 1' > "$dir/pareto.tsv"
    # short labels: the knob for the sample and projection variants (the curve's colour gives the family)
    rows "$size" '' | awk -F'\t' -v OFS='\t' '{ $7 = $2; sub(/.*samples /, "s=", $7);
        sub(/.*projection /, "p=", $7); sub(/^five per_channel$/, "per_channel", $7); print }' > "$dir/all.tsv"
    gnuplot <<EOF
set terminal pngcairo size 1100,750 font ",11" noenhanced
set output "$out"
set datafile separator "\t"
set title "Speed/accuracy trade at ${size}x${size} against ${truth} (median over all cases)"
set logscale x
set xtics (5, 7, 10, 15, 20, 30, 40, 50, 70, 100, 150, 200, 300, 500, 700, 1000)
set xlabel "median warm frame time, ms (log scale)"
set ylabel "median relative L2 error"
set grid
set autoscale xfix
set offsets graph 0.05, graph 0.12, graph 0.06, graph 0.06
set key top right
# labels of neighbouring (by time) modes are staggered up and down so they overlap less
plot "$dir/pareto.tsv" using 3:4 with lines dashtype 2 linewidth 3 linecolor rgb "#999999" title "Pareto front", \
     "$dir/single.tsv" using 3:4 with linespoints pointtype 7 pointsize 1.5 title "single (samples 16, 64)", \
     "$dir/samples.tsv" using 3:4 with linespoints pointtype 5 pointsize 1.5 title "five, samples 4-64", \
     "$dir/projection.tsv" using 3:4 with linespoints pointtype 9 pointsize 1.5 title "five, projection 128-1024", \
     "$dir/per_channel.tsv" using 3:4 with points pointtype 13 pointsize 2 title "five per_channel", \
     "$dir/profiles.tsv" using 3:4 with points pointtype 11 pointsize 2 title "five, other profiles", \
     "$dir/auto.tsv" using 3:4 with points pointtype 15 pointsize 2 title "auto", \
     "$dir/all.tsv" using 3:(\$4 * (1 + 0.03 * (int(\$0) % 2 ? 1 : -1))):7 with labels left offset 0.6,0 \
         font ",9" notitle
EOF
    echo "plot_trade.sh: wrote $out"
}

for size in $(awk -F'\t' 'NR > 1 { print $1 }' "$tsv" | sort -un); do
    plot_size "$size"
done
