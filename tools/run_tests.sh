#!/usr/bin/env bash
# Runs every prism test: formatting and lints, the Rust tests (release mode), and the Python
# tests in tools/tests against Mitsuba 3 and colour-science. Installs what it needs: the Python
# venv tools/.venv with the prism_tools package (tools/pyproject.toml) and its pinned requirements
# (tools/requirements.txt), re-installed when either file changes.
set -euo pipefail
cd "$(dirname "$0")/.."

py=$(command -v python3.11 || command -v python3)
venv=tools/.venv
stamp="$venv/.requirements.sha256"
want=$(cat tools/requirements.txt tools/pyproject.toml | sha256sum | cut -d' ' -f1)
if [ ! -x "$venv/bin/python" ] || [ "$(cat "$stamp" 2>/dev/null)" != "$want" ]; then
    echo "== installing the Python environment ($venv)"
    "$py" -m venv "$venv"
    "$venv/bin/pip" install --quiet --upgrade pip
    "$venv/bin/pip" install --quiet -r tools/requirements.txt -e tools
    echo "$want" > "$stamp"
fi

echo "== cargo fmt --check"
cargo fmt --all -- --check
echo "== cargo clippy (release, all targets, warnings are errors)"
cargo clippy --release --all-targets --quiet -- -D warnings
echo "== cargo test --release"
cargo test --release
echo "== pytest tools/tests"
PRISM_BIN="$PWD/target/release/prism" "$venv/bin/python" -m pytest -q tools/tests
