"""Checks that every AVX-512 instruction of a compiled library is in width-16 code.

Usage: check_avx512_isolation.py LIBRARY_OR_OBJECT...   (run by ctest: avx512_only_in_width_16)

The width-16 kernels are AVX-512 and must run only where CPUID says so (core/cpu.cpp). Their
own code lives in the patina::target_avx512 namespace (core/simd/target.h) or is a *_w16()
table, reached through the dispatcher. Any other global function holding AVX-512 code -- a
helper, or a library template (std::vector's growth) instantiated in a width-16 unit, of which
the linker keeps one copy for every width -- would run on CPUs without AVX-512 and fault there;
CMakeLists.txt makes such copies local to the width-16 object (patina_private_avx512_object),
where only width-16 code can call them. This scans every function of the given objects,
archives or executables (not stripped) for EVEX-encoded instructions (first opcode byte 0x62
after address-size or segment prefixes: 0x62 is no instruction of its own in 64-bit mode) and
opmask instructions (k*), and fails naming each global or weak function outside the width-16
code that has one.
"""

from __future__ import annotations

import re
import subprocess
import sys

PREFIXES = {"67", "2e", "3e", "26", "64", "65", "36"}
OPMASK = re.compile(r"k(mov|and|or|xor|not|test|ortest|shift|add|unpck)[bwdq]?$")
LINE = re.compile(r"^\s*[0-9a-f]+:\t((?:[0-9a-f]{2} )+)\s*\t(\S+)")
FUNCTION = re.compile(r"^([0-9a-f]+) <(.*)>:$")
SECTION = re.compile(r"^Disassembly of section (\S+):$")


SYMBOL = re.compile(r"^([0-9a-f]+) (.{7}) (\S+)\t[0-9a-f]+ (?:\.hidden |\.protected |\.internal )?(.*)$")


def avx512_functions(path: str) -> dict[tuple[str, bool], str]:
    """The functions with AVX-512 code, keyed by (name, local symbol), each with its first such
    instruction."""
    listing = subprocess.run(["objdump", "-d", "-t", "-C", "-w", path], check=True, capture_output=True, text=True)
    found: dict[tuple[str, bool], str] = {}
    function, local, section = None, set(), ""
    for line in listing.stdout.splitlines():
        if "file format" in line:  # the next archive member: its own symbol table
            local, function = set(), None
        elif (m := SYMBOL.match(line)) and m.group(2)[0] == "l" and m.group(2)[6] == "F":
            # by section and address: a local copy and a weak one of a template can share a name
            local.add((m.group(3), int(m.group(1), 16)))
        elif m := SECTION.match(line):
            section = m.group(1)
        elif m := FUNCTION.match(line):
            function = (m.group(2), (section, int(m.group(1), 16)) in local)
        elif (m := LINE.match(line)) and function is not None:
            code = m.group(1).split()
            while code and code[0] in PREFIXES:
                code = code[1:]
            if (code and code[0] == "62") or OPMASK.match(m.group(2)):
                found.setdefault(function, line.strip())
    return found


def main(paths: list[str]) -> int:
    if not paths:
        print(__doc__.strip().splitlines()[2], file=sys.stderr)
        return 2
    bad, inside = [], 0
    for path in paths:
        for (function, local), line in avx512_functions(path).items():
            if "target_avx512" in function or re.search(r"_w16\(\)", function):
                inside += 1
            elif not local:
                bad.append(f"{path}: {function}: {line}")
    for b in bad:
        print("AVX-512 outside the width-16 code:", b, file=sys.stderr)
    if inside == 0:
        print("no AVX-512 code found at all: were the *_w16.cpp units built?", file=sys.stderr)
        return 1
    print(f"{inside} functions with AVX-512 code, all in width-16 code" if not bad else f"{len(bad)} outside")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
