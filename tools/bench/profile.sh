#!/usr/bin/env bash
# Where a render's time goes: instructions per function under valgrind's callgrind, counted only
# inside prism's integrator::render (scene loading and the EXR writer are left out). Instruction
# counts are deterministic, so they compare builds and backends on a noisy or shared machine where
# timings cannot (and they need no hardware counters, which VMs often lack).
#
#   tools/bench/profile.sh [SCENE.ron] [SPP] [ACCEL] [SIMD]   # defaults: scenes/cornell.ron 1 bvh auto
#
# SIMD is `--simd`: auto (the packet kernel), off (the scalar integrator), 1, 4, 8, 16; a value
# other than auto is added to the output names.
#
# Uses $PRISM, default target/release/prism, as built (for ACCEL=embree, a build with
# --features embree, e.g. PRISM=target/embree/release/prism).
# Writes out/bench/profile/NAME_ACCEL.callgrind (open with kcachegrind or callgrind_annotate) and
# NAME_ACCEL.txt: the top functions by self instructions, and the share of ray queries (BVH or
# Embree traversal and primitive tests).
set -euo pipefail
cd "$(dirname "$0")/../.."
scene=${1:-scenes/cornell.ron}
spp=${2:-1}
accel=${3:-bvh}
simd=${4:-auto}
name=$(basename "$scene" .ron)
if [ "$simd" != auto ]; then name="${name}_simd_$simd"; fi
out=out/bench/profile
mkdir -p "$out"
cg="$out/${name}_${accel}.callgrind"
cmd=(valgrind --tool=callgrind --callgrind-out-file="$cg" '--toggle-collect=prism::integrator::render*'
     "${PRISM:-target/release/prism}" render "$scene" -o "$out/${name}.exr" --spp "$spp" --threads 1 -q --accel "$accel" --simd "$simd")
echo "\$ ${cmd[*]}"
"${cmd[@]}" 2>&1 | grep -E "rendered|refs" || true
report="$out/${name}_${accel}.txt"
{
    echo "command: ${cmd[*]}"
    callgrind_annotate --auto=no "$cg" 2>/dev/null | sed -n '/PROGRAM TOTALS/,$p' | head -34
    # Ray queries: prism's accel module, Scene::intersect (the BVH traversal inlines into it),
    # primitive tests, and everything inside libembree.
    callgrind_annotate "$cg" 2>/dev/null | awk '
        /PROGRAM TOTALS/ { gsub(",", "", $1); total = $1 }
        /:.*(Scene::intersect|PrimGeom::intersect|accel::|libembree|embree3::|prism_triangle_hit|triangle::intersect)/ {
            v = $1; gsub(",", "", v); rq += v }
        END { if (total > 0) printf "ray queries: %.1f%% of %d instructions\n", 100 * rq / total, total }'
} > "$report"
cat "$report"
