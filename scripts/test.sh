#!/usr/bin/env bash
# README command 2: every test. Rust unit and integration tests (release build: the paper's
# tables run fast), then the FMUs are built and driven by fmpy under pytest.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
scripts/system_deps.sh
python="$(scripts/env.sh)"
cargo test --release
scripts/build_fmus.sh
"$python" -m pytest -q pytests "$@"
