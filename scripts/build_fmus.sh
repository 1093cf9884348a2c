#!/usr/bin/env bash
# Builds the flexfmu library and CLI (release) and packages every shipped scene into
# build/fmus/<model_name>.fmu.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
cargo build --release --quiet
mkdir -p build/fmus
for scene in scenes/*.toml; do
    ./target/release/flexfmu build "$scene" -o "build/fmus/$(basename "$scene" .toml).fmu" >/dev/null
done
ls build/fmus/*.fmu
