#!/usr/bin/env bash
# README command 1: build the FMUs and run the demo with fmpy (plots go to build/demo/).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
python="$(scripts/env.sh)"
scripts/build_fmus.sh
"$python" scripts/demo.py
