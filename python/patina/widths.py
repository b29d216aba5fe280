"""The SIMD width argument every vectorised call takes (1, 4, 8, 16, or None for the default)."""

from __future__ import annotations

from patina.native import _core

# 16 is AVX-512 (F, VL, DQ, BW): accepted where the CPU runs it, and the default there (core/cpu.cpp).
WIDTHS = (1, 4, 8, 16)


def core_width(width: int | None) -> int:
    """None -> 0 (the C++ default: PATINA_SIMD or the widest path the CPU runs); else 1, 4, 8 or 16,
    checked against the CPU. ValueError otherwise."""
    if width is None:
        return 0
    if width not in WIDTHS:
        raise ValueError(f"width: must be None, 1, 4, 8 or 16, got {width!r}")
    if not _core.width_supported(width):
        why = " (it needs AVX-512)" if width == 16 else ""
        raise ValueError(f"width: {width}-wide SIMD is not supported on this CPU{why}")
    return int(width)
