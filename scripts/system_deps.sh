#!/usr/bin/env bash
# Debian packages the tests need: libtbb12 (the Ecos importer), libxml2-utils (xmllint against
# the FMI 2.0 schema), valgrind (leak check), binutils (nm: exported symbols).
set -euo pipefail
need=()
for p in libtbb12 libxml2-utils valgrind binutils; do
    dpkg -s "$p" >/dev/null 2>&1 || need+=("$p")
done
[ ${#need[@]} -eq 0 ] && exit 0
if [ "$(id -u)" = 0 ]; then
    apt-get update -qq >/dev/null
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${need[@]}" >/dev/null
elif command -v sudo >/dev/null 2>&1; then
    sudo apt-get update -qq >/dev/null
    sudo DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${need[@]}" >/dev/null
else
    echo "missing Debian packages: ${need[*]} (install them with apt-get)" >&2
    exit 1
fi
