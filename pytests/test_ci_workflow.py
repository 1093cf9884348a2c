"""The platform-matrix workflow (.github/workflows/fmus.yml, issue 14 item 4) cannot run on this
machine; what can be checked here is: it parses as YAML, it builds every one of the five FMI
2.0.4 platforms of the issue with a Rust target for that platform, its merge job names each
library where the build job uploads it, and its merge command, run with stand-in libraries,
gives an FMU with exactly those five binary folders."""
import pathlib
import re
import shlex
import shutil
import subprocess
import zipfile

import yaml

ROOT = pathlib.Path(__file__).resolve().parents[1]
WORKFLOW = ROOT / ".github" / "workflows" / "fmus.yml"
PLATFORMS = {"linux64", "aarch64-linux", "win64", "darwin64", "aarch64-darwin"}
TARGETS = {  # FMI folder -> (Rust target, library file name)
    "linux64": ("x86_64-unknown-linux-gnu", "libflexfmu.so"),
    "aarch64-linux": ("aarch64-unknown-linux-gnu", "libflexfmu.so"),
    "win64": ("x86_64-pc-windows-msvc", "flexfmu.dll"),
    "darwin64": ("x86_64-apple-darwin", "libflexfmu.dylib"),
    "aarch64-darwin": ("aarch64-apple-darwin", "libflexfmu.dylib"),
}


def load():
    text = WORKFLOW.read_text()
    assert "NOT RUN HERE" in text  # the header says it has not been executed
    return yaml.safe_load(text)


def merge_command(doc):
    step = next(s for s in doc["jobs"]["merge"]["steps"] if "flexfmu build" in s.get("run", ""))
    # the loop body: join continuation lines, take the flexfmu command
    body = step["run"].replace("\\\n", " ")
    return next(line.strip() for line in body.splitlines() if "flexfmu build" in line)


def test_workflow_parses_and_builds_the_five_platforms():
    doc = load()
    assert set(doc["jobs"]) == {"library", "merge"}
    assert doc["jobs"]["merge"]["needs"] == "library"
    include = doc["jobs"]["library"]["strategy"]["matrix"]["include"]
    assert {m["platform"] for m in include} == PLATFORMS
    for m in include:
        assert (m["target"], m["library"]) == TARGETS[m["platform"]], m
    # every build is checked for self-containedness by the script the Linux test runs
    runs = " ".join(s.get("run", "") for s in doc["jobs"]["library"]["steps"])
    assert "scripts/self_contained.py ${{ matrix.platform }}" in runs
    upload = next(s for s in doc["jobs"]["library"]["steps"] if s.get("uses", "").startswith("actions/upload-artifact"))
    assert upload["with"]["name"] == "lib-${{ matrix.platform }}"


def test_merge_command_gives_the_five_binary_folders(tmp_path):
    doc = load()
    args = shlex.split(merge_command(doc))
    libs = [args[i + 1] for i, a in enumerate(args) if a == "--library"]
    pairs = dict(lib.split("=", 1) for lib in libs)
    assert set(pairs) == PLATFORMS
    for platform, path in pairs.items():
        # download-artifact puts artifact lib-<platform> in libs/lib-<platform>/
        assert path == f"libs/lib-{platform}/{TARGETS[platform][1]}", path
        stand_in = tmp_path / path
        stand_in.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(ROOT / "target" / "release" / "libflexfmu.so", stand_in)
    (tmp_path / "fmus").mkdir()
    cmd = [a.replace("$scene", str(ROOT / "scenes" / "pendulum.toml"))
           .replace("$name", "pendulum").replace("./target/release/flexfmu", str(ROOT / "target" / "release" / "flexfmu"))
           for a in args]
    subprocess.run(cmd, cwd=tmp_path, check=True, capture_output=True)
    with zipfile.ZipFile(tmp_path / "fmus" / "pendulum.fmu") as z:
        bins = sorted(n for n in z.namelist() if n.startswith("binaries/"))
    ext = {"linux64": "so", "aarch64-linux": "so", "win64": "dll", "darwin64": "dylib", "aarch64-darwin": "dylib"}
    assert bins == sorted(f"binaries/{p}/pendulum.{ext[p]}" for p in PLATFORMS), bins
    assert re.search(r"for scene in scenes/\*\.toml", next(
        s["run"] for s in doc["jobs"]["merge"]["steps"] if "flexfmu build" in s.get("run", "")))
