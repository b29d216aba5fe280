"""Builds and runs the C++ tests with width 16 on SIMDe's emulated AVX-512 (libsimde-dev), to
check the width-16 code lane by lane against width 1 on a CPU without AVX-512.

Usage: python3 tools/avx512_emulation/run.py [BUILD_DIR]   (default: build/avx512-emulated)

Copies the checkout's tracked files to BUILD_DIR/src, makes that copy compile the width-16
units with -mavx2 -mfma and the SIMDe header (avx512_emu.h beside this script) instead of
-mavx512*, and cpu.cpp report width 16 as supported, then builds and runs patina_tests there.
Nothing in the checkout changes. Timings from such a build mean nothing: only correctness.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))

# (file, text, replacement): each text must occur once, or the script stops naming it.
PATCHES = [
    (
        "core/simd/target.h",
        "#if defined(__AVX512F__) && defined(__AVX512VL__)",
        "#if defined(PATINA_EMULATE_AVX512) || defined(__AVX512F__) && defined(__AVX512VL__)",
    ),
    ("core/simd/vec16_avx512.h", '#include "vec8_avx.h"\n', '#include "vec8_avx.h"\n#include "avx512_emu.h"\n'),
    ("core/cpu.cpp", "f.avx512 = f.avx2 && cpu_has_avx512();", "f.avx512 = f.avx2 || cpu_has_avx512();"),
    (
        "CMakeLists.txt",
        "set(PATINA_AVX512_FLAGS -mavx512f -mavx512vl -mavx512dq -mavx512bw -mavx2 -mfma)",
        f"set(PATINA_AVX512_FLAGS -mavx2 -mfma -DPATINA_EMULATE_AVX512 -I{HERE} -Wno-error)",
    ),
    # no AVX-512 instruction exists in an emulated build: the isolation check has nothing to see
    ("CMakeLists.txt", "if(PATINA_OBJDUMP AND Python3_Interpreter_FOUND)", "if(FALSE)"),
]


def main() -> int:
    if not os.path.exists("/usr/include/simde/x86/avx512.h"):
        print("needs SIMDe: apt-get install libsimde-dev", file=sys.stderr)
        return 2
    build = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build", "avx512-emulated"))
    src = os.path.join(build, "src")
    files = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, check=True, capture_output=True, text=True)
    for rel in filter(None, files.stdout.split("\0")):
        if os.path.isfile(os.path.join(ROOT, rel)):
            os.makedirs(os.path.dirname(os.path.join(src, rel)), exist_ok=True)
            shutil.copy2(os.path.join(ROOT, rel), os.path.join(src, rel))
    for rel, old, new in PATCHES:
        path = os.path.join(src, rel)
        with open(path) as f:
            text = f.read()
        if text.count(old) != 1:
            print(f"{rel}: expected once: {old!r}; update PATCHES in {__file__}", file=sys.stderr)
            return 1
        with open(path, "w") as f:
            f.write(text.replace(old, new))
    out = os.path.join(build, "out")
    config = ["-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release", "-DPATINA_BUILD_PYTHON=OFF", "-DPATINA_BUILD_TESTS=ON"]
    subprocess.run(["cmake", "-S", src, "-B", out, *config], check=True)
    subprocess.run(["cmake", "--build", out, "-j", str(os.cpu_count() or 2)], check=True)
    # the emulated CPU reports AVX2 as AVX-512 (the patch above); PATINA_SIMD=16 makes sure width 16 is the one run
    env = dict(os.environ, PATINA_SIMD="16")
    return subprocess.run([os.path.join(out, "patina_tests"), "--gtest_brief=1"], check=False, env=env).returncode


if __name__ == "__main__":
    sys.exit(main())
