#!/usr/bin/env bash
# Every speed figure of docs/performance.md in one command, on one machine, in one run:
#
#   tools/bench/run_all.sh            # full settings (about an hour on 2 cores); writes docs/bench/
#   tools/bench/run_all.sh --quick    # smoke check of every step (a few minutes); writes out/bench/quick/
#
# Steps (each prints the commands it runs):
#   1. tools/bench/bench.py        prism (BVH, Embree) vs Mitsuba 3: throughput, load, RSS, threads
#   2. tools/bench/error_time.py   relMSE against time, prism variants and Mitsuba, equal-error speedups
#   3. cargo bench --bench traversal   BVH vs Embree rays/s, 20k and 1M triangles
#   4. tools/bench/profile.sh      callgrind instruction profile of the Cornell box (BVH and Embree)
#                                  and of scenes/bench/metals, glass, plastics (packet and scalar)
# For issue 26 item 4 on a busy machine, tools/bench/versus_mitsuba.sh runs a smaller set.
# Uses tools/.venv (made by tools/run_tests.sh) for Python, and Embree when libembree-dev is
# installed. Run it on a quiet machine: the figures are only as good as the machine is idle.
set -euo pipefail
cd "$(dirname "$0")/../.."
quick=()
out=docs/bench
if [ "${1:-}" = "--quick" ]; then
    quick=(--quick)
    out=out/bench/quick
fi
mkdir -p "$out"
py=${PYTHON:-tools/.venv/bin/python}
features=()
# (No `grep -q`: under pipefail, ldconfig's SIGPIPE would read as "not installed".)
if ldconfig -p 2>/dev/null | grep 'libembree3\.so ' >/dev/null; then features=(--features embree); fi

# Mitsuba's LLVM variant needs libLLVM >= 19 (Debian's default 15 fails to compile its kernels);
# without it that variant's rows say so and the rest still runs.
if [ ! -e /usr/lib/x86_64-linux-gnu/libLLVM.so.19.1 ] && [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
    echo "== installing libllvm19 (apt-get) for Mitsuba's llvm_ad_spectral"
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq libllvm19 >/dev/null 2>&1 ||
        { apt-get update -qq >/dev/null 2>&1 || true; DEBIAN_FRONTEND=noninteractive apt-get install -y -qq libllvm19 >/dev/null 2>&1 || true; }
fi
echo "== machine: $(nproc) CPUs, load average $(cut -d' ' -f1-3 /proc/loadavg)"
echo "== 1. bench.py"
"$py" tools/bench/bench.py "${quick[@]}" --out "$out"
echo "== 2. error_time.py"
"$py" tools/bench/error_time.py "${quick[@]}" --out "$out"
echo "== 3. traversal"
echo "\$ cargo bench --bench traversal ${features[*]} -- ${quick[*]}"
cargo bench --quiet --bench traversal "${features[@]}" -- "${quick[@]}" | tee "$out/traversal.md"
echo "== 4. profile"
cargo build --release --quiet
tools/bench/profile.sh scenes/cornell.ron 1 bvh | tee "$out/profile_cornell_bvh.txt"
for s in metals glass plastics; do
    for simd in auto off; do
        tools/bench/profile.sh "scenes/bench/$s.ron" 1 bvh "$simd" | tee "$out/profile_${s}_$simd.txt"
    done
done
if [ ${#features[@]} -gt 0 ]; then
    cargo build --release --quiet "${features[@]}" --target-dir target/embree
    PRISM=target/embree/release/prism tools/bench/profile.sh scenes/cornell.ron 1 embree | tee "$out/profile_cornell_embree.txt"
fi
echo "== done: results in $out/"
