#!/usr/bin/env python3
"""Checks that `rust-version` in Cargo.toml equals the largest `rust-version` that a normal or
build dependency in Cargo.lock declares (edition 2024 needs at least 1.85). Runs
`cargo metadata`, which may download the manifests of crates for other targets.

    python3 scripts/check_rust_version.py
"""
import json
import pathlib
import re
import subprocess
import sys

root = pathlib.Path(__file__).resolve().parent.parent
meta = json.loads(subprocess.run(["cargo", "metadata", "--format-version", "1"], cwd=root,
                                 check=True, capture_output=True, text=True).stdout)
packages = {p["id"]: p for p in meta["packages"]}
nodes = {n["id"]: n for n in meta["resolve"]["nodes"]}
top = meta["resolve"]["root"]
seen, stack = set(), [top]
while stack:
    for dep in nodes[stack.pop()]["deps"]:
        if any(k["kind"] in (None, "build") for k in dep["dep_kinds"]) and dep["pkg"] not in seen:
            seen.add(dep["pkg"])
            stack.append(dep["pkg"])


def key(v):
    return tuple(int(x) for x in v.split("."))[:2]


need = max([((1, 85), "edition 2024")] + [
    (key(packages[i]["rust_version"]), f'{packages[i]["name"]} {packages[i]["version"]}')
    for i in seen if packages[i].get("rust_version")])
declared = re.search(r'^rust-version\s*=\s*"([0-9.]+)"', (root / "Cargo.toml").read_text(), re.M)
have = key(declared.group(1))
print(f"dependencies need {need[0][0]}.{need[0][1]} ({need[1]}); Cargo.toml says {declared.group(1)}")
sys.exit(0 if have == need[0] else 1)
