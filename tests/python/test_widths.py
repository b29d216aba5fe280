"""The SIMD widths: 16 (AVX-512) is chosen from CPUID at run time, the default where the CPU has
it, never reached on a CPU without it (PATINA_SIMD=8 forces 8); the Python side accepts exactly
the widths the C++ dispatcher does."""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import pytest

from patina.native import _core
from patina.widths import WIDTHS, core_width

AVX512 = ("avx512f", "avx512vl", "avx512dq", "avx512bw")


def _cpu_flags() -> set[str] | None:
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("flags"):
                    return set(line.split(":", 1)[1].split())
    except OSError:
        pass
    return None


def _in_subprocess(env_value: str | None, expression: str) -> subprocess.CompletedProcess:
    env = {k: v for k, v in os.environ.items() if k != "PATINA_SIMD"}
    if env_value is not None:
        env["PATINA_SIMD"] = env_value
    code = f"from patina.native import _core; print({expression})"
    command = [sys.executable, "-c", code]
    return subprocess.run(command, check=False, env=env, capture_output=True, text=True, timeout=120)


def _cpu_has_avx512() -> bool:
    flags = _cpu_flags()
    if flags is None:
        pytest.skip("no /proc/cpuinfo")
    return all(f in flags for f in AVX512)


def test_width_16_is_known_everywhere():
    assert WIDTHS == (1, 4, 8, 16)


def test_width_16_is_offered_exactly_where_the_cpu_reports_avx512():
    r = _in_subprocess(None, "_core.width_supported(16)")
    assert r.returncode == 0 and r.stdout.strip() == str(_cpu_has_avx512()), r.stderr


def test_width_16_supported_exactly_when_asked_and_the_cpu_reports_avx512():
    """The CPUID + XGETBV check agrees with the kernel's view of the CPU (which also needs the
    OS to save the ZMM state: Linux lists avx512* only when it does)."""
    r = _in_subprocess("16", "_core.width_supported(16), _core.width_supported(8)")
    assert r.returncode == 0, r.stderr
    assert r.stdout.split() == [str(_cpu_has_avx512()), "True"]


def test_the_default_is_the_widest_supported_width_and_patina_simd_8_forces_8():
    r = _in_subprocess(None, "_core.default_width()")
    assert r.returncode == 0, r.stderr
    assert int(r.stdout) == max(w for w in (1, 4, 8, 16) if _core.width_supported(w))
    if _core.width_supported(8):
        r = _in_subprocess("8", "_core.default_width(), _core.width_supported(16)")
        assert r.returncode == 0, r.stderr
        assert r.stdout.split() == ["8", str(_cpu_has_avx512())]


@pytest.mark.parametrize("value", ["16", "avx512"])
def test_patina_simd_16_without_avx512_is_refused(value):
    if _cpu_has_avx512():
        pytest.skip("this CPU runs width 16")
    r = _in_subprocess(value, "_core.default_width()")
    assert r.returncode != 0 and f"PATINA_SIMD={value}: this CPU cannot run that path" in r.stderr


def test_width_16_without_avx512_is_refused_before_any_kernel_runs():
    if _core.width_supported(16):
        assert core_width(16) == 16
        return
    with pytest.raises(ValueError, match="16-wide SIMD is not supported on this CPU"):
        core_width(16)
    # the C++ side refuses it too, for callers that bypass patina.widths
    with pytest.raises(ValueError, match="width=16: this CPU cannot run that path"):
        _core.math("acos", np.full(16, 0.5, np.float32), width=16)
