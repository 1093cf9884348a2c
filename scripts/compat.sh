#!/usr/bin/env bash
# Regenerates compat/ (issue 14, item 5): for five shipped scenes the FMU, its reference result,
# input signals, options and readme in the FMI Cross-Check layout, and the importers' results
# (FMPy, libcosim, Ecos) with a summary in compat/README.md. The FMUs are not committed
# (.gitignore). Arguments go to scripts/compat.py (--out DIR, --only MODEL...).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
cargo build --release --quiet
python="$(scripts/env.sh)"
exec "$python" scripts/compat.py "$@"
