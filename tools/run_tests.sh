#!/usr/bin/env bash
# Runs every prism test: formatting and lints, the Rust tests (release mode), the Python tests in
# tools/tests against Mitsuba 3 and colour-science, and the Embree backend (cargo feature `embree`:
# its lints and the accelerator tests). Installs what it needs: the Python venv tools/.venv with the
# prism_tools package (tools/pyproject.toml) and its pinned requirements (tools/requirements.txt),
# re-installed when either file changes; the prism Python module (python/, maturin), re-installed
# when its or prism's sources change; and Debian's libembree-dev through apt-get when it is
# missing and this runs as root with apt available; if Embree cannot be had, only the Embree part
# is skipped, with a loud notice.
set -euo pipefail
cd "$(dirname "$0")/.."

# Each step's heading carries the seconds since the start, so a slow CI run shows where its time
# went; the free disk is printed once because a full disk fails the build in confusing ways.
step() { echo "== $* [${SECONDS}s]"; }
df -h . 2>/dev/null | tail -1 | awk '{print "== disk: " $4 " free of " $2}'

py=$(command -v python3.11 || command -v python3)
venv=tools/.venv
stamp="$venv/.requirements.sha256"
want=$(cat tools/requirements.txt tools/pyproject.toml | sha256sum | cut -d' ' -f1)
if [ ! -x "$venv/bin/python" ] || [ "$(cat "$stamp" 2>/dev/null)" != "$want" ]; then
    step "installing the Python environment ($venv)"
    "$py" -m venv "$venv"
    "$venv/bin/pip" install --quiet --upgrade pip
    "$venv/bin/pip" install --quiet -r tools/requirements.txt -e tools
    echo "$want" > "$stamp"
fi

# The prism Python module (python/, README "Python"): built by maturin into the venv, again
# whenever its sources or prism's change. It builds in the release profile in the workspace's
# target/, which the cargo steps below share, so only the module's own crate is added.
pystamp="$venv/.prism-module.sha256"
pywant=$(find Cargo.toml Cargo.lock build.rs src spectra python/Cargo.toml python/pyproject.toml python/src \
    -type f -print0 | LC_ALL=C sort -z | xargs -0 cat | sha256sum | cut -d' ' -f1)
if [ "$(cat "$pystamp" 2>/dev/null)" != "$pywant" ]; then
    step "installing the prism Python module (python/) into $venv"
    "$venv/bin/pip" install --quiet "maturin>=1.8,<2"
    # The venv's bin/ on PATH: without build isolation, pip runs the maturin found there.
    PATH="$PWD/$venv/bin:$PATH" "$venv/bin/pip" install --quiet --no-build-isolation --no-deps \
        --force-reinstall ./python
    echo "$pywant" > "$pystamp"
fi

# torch, for the DataLoader test only (tools/tests/test_python_dataset_workers.py): not a
# requirement of prism, and PyPI's Linux wheel brings its CUDA libraries (~3 GB to download,
# about 2 minutes here), so it is installed once beside the requirements, not pinned in them.
# Where it cannot be had, the run goes on and that one test skips with its reason.
torchstamp="$venv/.torch-tried"
if [ ! -e "$torchstamp" ]; then
    step "installing torch into $venv (for the DataLoader test)"
    timeout 900 "$venv/bin/pip" install --quiet --no-cache-dir torch ||
        echo "notice: torch could not be installed; the DataLoader test will skip" >&2
    touch "$torchstamp"
fi

# Embree 3 for the `embree` feature: present when its pkg-config file or library is there.
have_embree() {
    # No `grep -q`: it stops reading early, ldconfig then dies of SIGPIPE, and pipefail turns
    # that into a failure.
    pkg-config --exists embree3 2>/dev/null || ldconfig -p 2>/dev/null | grep 'libembree3\.so ' >/dev/null ||
        compgen -G '/usr/lib/*/libembree3.so' >/dev/null
}
if ! have_embree && [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
    step "installing libembree-dev (apt-get) for the embree feature"
    # DEBIAN_FRONTEND: CI has no terminal to answer prompts.
    if ! DEBIAN_FRONTEND=noninteractive apt-get install -y -qq libembree-dev >/dev/null 2>&1; then
        apt-get update -qq >/dev/null 2>&1 || true
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq libembree-dev >/dev/null 2>&1 || true
    fi
fi
embree=0
if have_embree; then embree=1; fi
# CI sets PRISM_REQUIRE_EMBREE=1: there a missing Embree fails the run instead of being skipped.
if [ "$embree" = 0 ] && [ "${PRISM_REQUIRE_EMBREE:-0}" = 1 ]; then
    echo "error: PRISM_REQUIRE_EMBREE=1 but Embree 3 (Debian: libembree-dev) is not installed" >&2
    exit 1
fi

step "cargo fmt --check"
cargo fmt --all -- --check
step "cargo clippy (release, all targets and the Python module, warnings are errors)"
cargo clippy --release --workspace --all-targets --quiet -- -D warnings
# --workspace on every cargo step: cargo unifies dependency features over the packages it builds,
# and the Python module's (pyo3) enable more of syn and once_cell than prism alone does. Built for
# prism alone, every proc macro and all that depends on serde would be compiled a second time
# beside the module's build (`cargo +nightly test --unit-graph -Z unstable-options` shows the
# difference); over the workspace the module's build above and these steps share one tree.
step "cargo test --release"
# Without the feature: the Embree tests report as ignored here and run in the embree step.
PRISM_REQUIRE_EMBREE=0 cargo test --release --workspace
if [ "$embree" = 1 ]; then
    step "cargo clippy --features embree (release, all targets, warnings are errors)"
    cargo clippy --release --workspace --all-targets --features prism/embree --quiet -- -D warnings
    # The backend against brute force, the CLI's --accel, scale robustness (1e-4 to 1e5) and
    # whole images against the BVH's; PRISM_REQUIRE_EMBREE=1 makes tests/embree.rs fail if the
    # feature did not make it into the build.
    step "cargo test --release --features embree --test accel --test cli --test stability --test embree"
    PRISM_REQUIRE_EMBREE=1 cargo test --release --workspace --features prism/embree --test accel --test cli --test stability --test embree
else
    echo
    echo "!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!"
    echo "!! NOTICE: Embree 3 (Debian: libembree-dev) is not installed and could not be      !!"
    echo "!! installed here: SKIPPING the embree feature's clippy and tests (all else runs). !!"
    echo "!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!"
    echo
fi
step "pytest tools/tests"
PRISM_BIN="$PWD/target/release/prism" "$venv/bin/python" -m pytest -q --durations=10 tools/tests
step "done"
