#!/usr/bin/env bash
# The 20-moment version of tests/dataset_runs.rs's kill test: `prism dataset` on
# configs/datasets/smoke.ron is killed with SIGKILL at 20 seeded moments; after each kill every
# listed frame must be intact and still listed, none twice, and the resumed dataset must end
# byte-identical to an uninterrupted run. CI runs 5 moments (the default).
# Run from the repository root: tools/bench/dataset_kill.sh
set -euo pipefail
PRISM_KILLS=${PRISM_KILLS:-20} cargo test --release --test dataset_runs \
    resume_after_kill_loses_nothing_and_ends_identical -- --nocapture
