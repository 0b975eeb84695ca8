#!/usr/bin/env bash
# Issue 26 item 4's figures in one run, sized for the shared 2-core machine (a few minutes per
# step, not an hour): prism's packet kernel (`--simd auto`) and scalar integrator (`--simd off`)
# against Mitsuba 3.9.1 `scalar_spectral` and `llvm_ad_spectral`, interleaved rounds
# (tools/bench/rounds.py), the load average recorded before every render.
#
#   tools/bench/versus_mitsuba.sh OUT_DIR [NAME=BINARY ...]
#
# Each NAME=BINARY is another prism build whose packet kernel joins the same rounds (e.g.
# after=/tmp/prism_speed). Uses $PRISM (default target/release/prism, not rebuilt) and
# $PYTHON (default tools/.venv/bin/python). Steps, each into OUT_DIR:
#   1. cornell_throughput.py  Mitsuba's own cornell_box(), 16 spp, 5 rounds
#   2. bench.py               materials, 1M-triangle mesh, metals, glass, plastics; 2 threads, 5 rounds
#   3. error_time.py          Cornell, materials, mesh: ladders to 8 spp, references at 64 spp (a busy machine)
#   4. dataset_bench.py       configs/datasets/tabletop.ron at its own size and spp, 8 frames in 2 processes
#   5. profile.sh             callgrind of metals, glass, plastics (1 spp, 1 thread; packet and scalar)
# STEPS="1 2" runs a subset; BENCH_SCENES the scenes of step 2; ROUNDS (default 5) and BENCH_SPP (default bench.py's per scene)
# shrink it further on a busy machine.
set -euo pipefail
cd "$(dirname "$0")/../.."
out=${1:?usage: tools/bench/versus_mitsuba.sh OUT_DIR [NAME=BINARY ...]}
shift
prism=${PRISM:-target/release/prism}
py=${PYTHON:-tools/.venv/bin/python}
steps=${STEPS:-1 2 3 4 5}
rounds=${ROUNDS:-5}
bench_spp=()
if [ -n "${BENCH_SPP:-}" ]; then bench_spp=(--spp "$BENCH_SPP"); fi
also=()
for a in "$@"; do also+=(--also "$a"); done
mkdir -p "$out"
stamp() { echo "== $1: $(date -u +%FT%TZ), $(uptime)"; }
run() { echo "\$ $*"; "$@"; }
for step in $steps; do
    case $step in
    1) stamp "1. cornell_throughput.py" | tee -a "$out/log.txt"
       run "$py" tools/bench/cornell_throughput.py --prism "$prism" --spp 16 --repeats "$rounds" --threads 2 \
           --json "$out/cornell.json" "${also[@]}" 2>&1 | tee "$out/cornell.txt" ;;
    2) stamp "2. bench.py" | tee -a "$out/log.txt"
       run "$py" tools/bench/bench.py --prism "$prism" --scenes "${BENCH_SCENES:-materials,mesh,metals,glass,plastics}" \
           --threads 2 --repeats "$rounds" "${bench_spp[@]}" --out "$out" "${also[@]}" 2>&1 | tail -n 200 > "$out/bench.txt" ;;
    3) stamp "3. error_time.py" | tee -a "$out/log.txt"
       run "$py" tools/bench/error_time.py --prism "$prism" --scenes cornell,materials,mesh \
           --variants "prism,prism scalar" --max-spp 8 --ref-spp 64 --threads 2 \
           --out "$out" 2>&1 | tail -n 120 > "$out/error_time.txt" ;;
    4) stamp "4. dataset_bench.py" | tee -a "$out/log.txt"
       PRISM_BIN=$prism run "$py" tools/bench/dataset_bench.py --config configs/datasets/tabletop.ron \
           --frames 8 --chunk 4 --size 0 --skip-rss --lone-scalar 2>&1 | tee "$out/dataset.txt" ;;
    5) stamp "5. profile.sh" | tee -a "$out/log.txt"
       for s in metals glass plastics; do
           for simd in auto off; do
               PRISM=$prism tools/bench/profile.sh "scenes/bench/$s.ron" 1 bvh "$simd" > "$out/profile_${s}_$simd.txt" 2>&1
           done
       done ;;
    esac
    stamp "done $step" | tee -a "$out/log.txt"
done
