#!/bin/bash
# Issue 18's item 4 on a discrete GPU, in one run: `vkgi profile` of LPV and ILPV (one lattice,
# 8 steps a frame, as seed 000's Table 4.2 measured them) for every kernel (tiled, naive,
# column, single-column) and channel plan (a dispatch per channel, sequential or one compute
# queue each; the channels fused), and the column kernels fused with the lattices' cells in
# columns (`--cell-order columns`, which a GPU does not choose itself: its lanes hold
# neighbouring x; with the texel lookup columns need, so their frame differs in the lookup
# too: compare their steps), each lattice size in its own process (a size the device cannot hold fails
# alone), then one table of them (benches/gpu/item4_table.py). Not part of
# CI or `cargo bench`: it needs no build tools, only a built vkgi, so it can run where the GPU is.
#   bash benches/gpu/item4.sh [VKGI] [OUT]        (defaults: target/release/vkgi, item4)
# Environment: METHODS (lpv ilpv), LATTICES (32 64 128 256), SIZE (1920x1080), FRAMES (5), DEVICE (vkgi's
# --device: a substring of the GPU's name; default: vkgi's own choice), KERNELS (tiled naive
# column single-column), PLANS (separate-sequential separate-async fused-sequential),
# COLUMN_KERNELS (column single-column: those also run with cells in columns; empty for none),
# RUN_TIMEOUT (seconds a profile may take before it counts as failed: 300). A subset lets a short
# lease measure the variants it needs most first; the table reads every profile in OUT.
# Results: docs/performance.md ("Where issue 18's targets stand", item 4).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
vkgi=${1:-target/release/vkgi}
out=${2:-item4}
lattices=${LATTICES:-32 64 128 256}
size=${SIZE:-1920x1080}
frames=${FRAMES:-5}
methods=${METHODS:-lpv ilpv}
kernels=${KERNELS:-tiled naive column single-column}
plans=${PLANS:-separate-sequential separate-async fused-sequential}
column_kernels=${COLUMN_KERNELS-column single-column}
run_timeout=${RUN_TIMEOUT:-300}
device=()
if [ -n "${DEVICE:-}" ]; then device=(--device "$DEVICE"); fi
mkdir -p "$out"
written=()
for method in $methods; do
  # ILPV on one lattice, as the thesis measured it (its default is two scales).
  one_lattice=()
  if [ "$method" = ilpv ]; then one_lattice=(--far-lattice off); fi
  variants=()
  for kernel in $kernels; do
    for plan in $plans; do
      variants+=("$kernel $plan auto")
    done
  done
  for kernel in $column_kernels; do variants+=("$kernel fused-sequential columns"); done
  for variant in "${variants[@]}"; do
    read -r kernel plan order <<< "$variant"
    cells=()
    label="$kernel"
    if [ "$order" = columns ]; then
      cells=(--cell-order columns --lookup-filter texels)
      label="$kernel-columns"
    fi
    for lattice in $lattices; do
      name="$method-$label-$plan-$lattice"
      echo "== $name" >&2
      if timeout "$run_timeout" "$vkgi" profile --method "$method" --lattice "$lattice" --iterations 8 \
        ${one_lattice[@]+"${one_lattice[@]}"} --kernel "$kernel" \
        --channel-plan "${plan%-*}" --parts "${plan#*-}" ${cells[@]+"${cells[@]}"} \
        --size "$size" --frames "$frames" --warmup 1 ${device[@]+"${device[@]}"} \
        --json "$out/$name.json" > "$out/$name.txt" 2>&1; then
        written+=("$out/$name.json")
      else
        echo "failed: $name (see $out/$name.txt)" >&2
      fi
    done
  done
done
if [ ${#written[@]} -eq 0 ]; then
  echo "no profile ran" >&2
  exit 1
fi
python3 "$here/item4_table.py" "$out"/*.json | tee "$out/table.md"
