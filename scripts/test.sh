#!/usr/bin/env bash
# README command 2: every test. Formatting and lints first (cargo fmt --check, cargo clippy on
# all targets with warnings as errors), then the Rust unit and integration tests (release build:
# the paper's tables run fast; includes a slice of the FMI call-sequence fuzzer), then the FMUs
# are built and driven by fmpy under pytest.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
scripts/system_deps.sh
python="$(scripts/env.sh)"
for component in rustfmt clippy; do
    if ! cargo "${component/rustfmt/fmt}" --version >/dev/null 2>&1; then
        echo "the Rust component $component is missing: add it with 'rustup component add $component'" >&2
        exit 1
    fi
done
cargo fmt --check
cargo clippy --release --all-targets -- -D warnings
cargo test --release
scripts/build_fmus.sh
"$python" -m pytest -q pytests "$@"
