#!/usr/bin/env python3
"""Is a flexfmu library self-contained? Lists the shared libraries it asks the dynamic loader for
(ELF NEEDED entries, Mach-O LC_LOAD_DYLIB, PE import table; read with `objdump -p`, or with
`llvm-objdump` from rustup's llvm-tools where no GNU objdump reads the format) and checks them
against the operating system's C library family (issue 14, item 4: "no runtime dependencies
beyond the C library"):

- Linux: libc, libm, libgcc_s (unwinding: the library is built with panic = "unwind"),
  libpthread, libdl, the loader ld-linux and the kernel's linux-vdso;
- macOS: libSystem (the C library there; the Rust standard library links nothing else);
- Windows: the system DLLs of the Win32 API (kernel32, ntdll, advapi32, userenv, ws2_32, bcrypt,
  bcryptprimitives, api-ms-win-core-*); the Visual C++ runtime (vcruntime, msvcp, ucrt's
  api-ms-win-crt-*) is not allowed: it is linked statically (`-C target-feature=+crt-static`).
  Only Linux is checked on this project's machine (pytests/test_self_contained.py); the macOS
  and Windows lists are written for .github/workflows/fmus.yml and have not been run.

Usage: self_contained.py PLATFORM LIBRARY   (PLATFORM: an FMI binaries/ folder name, e.g. linux64)
Exit status 0 when every dependency is allowed; the dependencies are printed either way.
"""
import pathlib
import re
import shutil
import subprocess
import sys

ALLOWED = {
    "linux": [r"libc\.so\.\d+", r"libm\.so\.\d+", r"libgcc_s\.so\.\d+", r"libpthread\.so\.\d+",
              r"libdl\.so\.\d+", r"ld-linux[-\w.]*\.so\.\d+", r"linux-vdso\.so\.\d+"],
    "darwin": [r"/usr/lib/libSystem\.B\.dylib"],
    "win": [r"kernel32\.dll", r"ntdll\.dll", r"advapi32\.dll", r"userenv\.dll", r"ws2_32\.dll",
            r"bcrypt\.dll", r"bcryptprimitives\.dll", r"api-ms-win-core-[\w-]+\.dll"],
}


def family(platform):
    """The operating system of an FMI binaries/ folder name: linux, darwin or win."""
    for os_name in ALLOWED:
        if os_name in platform:
            return os_name
    raise ValueError(f"unknown platform folder {platform!r}")


def objdump():
    """GNU objdump if installed, else llvm-objdump from rustup's llvm-tools; None if neither."""
    exe = shutil.which("objdump") or shutil.which("llvm-objdump")
    if exe:
        return exe
    try:
        sysroot = subprocess.run(["rustc", "--print", "sysroot"], capture_output=True, text=True,
                                 check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return None
    found = sorted(pathlib.Path(sysroot).glob("lib/rustlib/*/bin/llvm-objdump*"))
    return str(found[0]) if found else None


def needed(library, os_name, exe=None):
    """The shared libraries `library` names for the dynamic loader, as written in the file."""
    exe = exe or objdump()
    if exe is None:
        raise FileNotFoundError("no objdump or llvm-objdump")
    if os_name == "darwin":
        out = subprocess.run([exe, "--macho", "--dylibs-used", str(library)], capture_output=True,
                             text=True, check=True).stdout
        # first line: the file name; then one "\t<path> (compatibility version ...)" per dylib,
        # like otool -L, which lists a dylib's own install name (LC_ID_DYLIB) too: left out
        names = [line.split(" (")[0].strip() for line in out.splitlines()[1:] if line.strip()]
        own = pathlib.PurePath(library).name
        return [n for n in names if pathlib.PurePath(n).name != own]
    out = subprocess.run([exe, "-p", str(library)], capture_output=True, text=True, check=True).stdout
    if os_name == "linux":
        return re.findall(r"^\s*NEEDED\s+(\S+)", out, flags=re.M)
    return re.findall(r"DLL Name:\s*(\S+)", out)


def disallowed(names, os_name):
    """The entries of `names` outside the C library family of `os_name` (case-insensitive on
    Windows, whose file names are)."""
    flags = re.I if os_name == "win" else 0
    return [n for n in names if not any(re.fullmatch(p, n, flags) for p in ALLOWED[os_name])]


def main(argv):
    if len(argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    os_name = family(argv[1])
    names = needed(argv[2], os_name)
    print("\n".join(names))
    bad = disallowed(names, os_name)
    if bad:
        print(f"not part of the C library family: {', '.join(bad)}", file=sys.stderr)
        return 1
    if not names:
        print("no dependencies found: is this a shared library?", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
