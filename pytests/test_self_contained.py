"""The library inside the FMUs needs nothing beyond the C library family (issue 14, item 4):
its ELF NEEDED entries (objdump -p) and what the dynamic loader resolves (ldd) are only libc,
libm, libgcc_s, libpthread, libdl, ld-linux and linux-vdso, with no RPATH/RUNPATH; the check
itself is scripts/self_contained.py, which .github/workflows/fmus.yml runs on every platform."""
import importlib.util
import pathlib
import re
import shutil
import subprocess
import zipfile

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
_spec = importlib.util.spec_from_file_location("self_contained", ROOT / "scripts" / "self_contained.py")
sc = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(sc)


@pytest.fixture(scope="module")
def library(fmus, tmp_path_factory):
    """The linux64 library of the pendulum FMU, extracted; every other shipped FMU carries the
    same file (same size and CRC-32), so checking one checks all."""
    entries = {}
    for name, path in fmus.items():
        with zipfile.ZipFile(path) as z:
            libs = [i for i in z.infolist() if i.filename.startswith("binaries/linux64/")]
            assert len(libs) == 1, (name, [i.filename for i in libs])
            entries[name] = (libs[0].file_size, libs[0].CRC)
    assert len(set(entries.values())) == 1, entries
    d = tmp_path_factory.mktemp("lib")
    with zipfile.ZipFile(fmus["pendulum"]) as z:
        name = next(n for n in z.namelist() if n.startswith("binaries/linux64/"))
        return pathlib.Path(z.extract(name, d))


def test_needed_entries_are_the_c_library_family(library):
    if sc.objdump() is None:
        pytest.skip("no objdump or llvm-objdump on this machine")
    names = sc.needed(library, "linux")
    assert any(re.fullmatch(r"libc\.so\.\d+", n) for n in names), names
    assert sc.disallowed(names, "linux") == [], names
    assert subprocess.run(["python3", str(ROOT / "scripts" / "self_contained.py"), "linux64", str(library)],
                          capture_output=True).returncode == 0


def test_no_rpath_and_ldd_resolves_only_the_c_library(library):
    if shutil.which("ldd") is None or sc.objdump() is None:
        pytest.skip("ldd or objdump missing")
    dyn = subprocess.run([sc.objdump(), "-p", str(library)], capture_output=True, text=True, check=True).stdout
    assert not re.search(r"^\s*(RPATH|RUNPATH)\s", dyn, flags=re.M)
    out = subprocess.run(["ldd", str(library)], capture_output=True, text=True, check=True).stdout
    assert "not found" not in out, out
    # "libm.so.6 => /lib/x86_64-linux-gnu/libm.so.6 (0x...)", "/lib64/ld-linux-x86-64.so.2 (0x...)"
    resolved = [pathlib.PurePath(line.split("=>")[0].split(" (")[0].strip()).name for line in out.splitlines()]
    assert len(resolved) >= 3, out
    assert sc.disallowed(resolved, "linux") == [], out


def test_the_check_rejects_a_real_dependency():
    """The checker is not vacuous: xmllint (installed by scripts/system_deps.sh) links libxml2."""
    exe = shutil.which("xmllint")
    if exe is None or sc.objdump() is None:
        pytest.skip("xmllint or objdump missing")
    bad = sc.disallowed(sc.needed(exe, "linux"), "linux")
    assert any(n.startswith("libxml2") for n in bad), bad
    # the Windows list rejects the Visual C++ runtime, the macOS list anything but libSystem
    assert sc.disallowed(["KERNEL32.dll", "VCRUNTIME140.dll", "api-ms-win-crt-heap-l1-1-0.dll"], "win") == [
        "VCRUNTIME140.dll", "api-ms-win-crt-heap-l1-1-0.dll"]
    assert sc.disallowed(["/usr/lib/libSystem.B.dylib", "/usr/lib/libc++.1.dylib"], "darwin") == [
        "/usr/lib/libc++.1.dylib"]
