"""The Brdf object: a tabulated BRDF with vectorised evaluation on the SIMD kernels."""

from __future__ import annotations

import contextlib
import os
import tempfile
from typing import Any

import numpy as np

from patina.file_names import engine_path, is_utf8, printable
from patina.native import _core
from patina.table.angles import angles_to_directions
from patina.widths import core_width


def _directions(name: str, w: Any) -> np.ndarray:
    a = np.asarray(w, dtype=np.float32)
    if a.ndim == 1 and a.shape[0] == 3:
        a = a[None, :]
    if a.ndim != 2 or a.shape[1] != 3:
        raise ValueError(f"{name} must have shape (n, 3), got {np.shape(w)}")
    return np.ascontiguousarray(a)


class Brdf:
    """A tabulated BRDF on an irregular grid.

    Evaluation runs on the coherent SIMD kernels: `width` forces a path (1 =
    scalar, 4 = SSE4.1, 8 = AVX2); None uses PATINA_SIMD or the widest the CPU has.
    """

    def __init__(self, table: _core.Table, source: str = "", source_format: str = "ptab") -> None:
        self._table = table
        self.source = source
        self.source_format = source_format

    # --- evaluation
    def eval(self, wi: Any, wo: Any, width: int | None = None, threads: int = 0) -> np.ndarray:
        """BRDF values (n, channels) for (n, 3) unit directions in the local frame.

        Directions at or below the horizon (z <= 0) give 0; angles outside the table's
        axes clamp to the axis ends.
        """
        a, b = _directions("wi", wi), _directions("wo", wo)
        if a.shape[0] != b.shape[0]:
            raise ValueError(f"wi has {a.shape[0]} rows but wo has {b.shape[0]}")
        return self._table.eval(a, b, width=core_width(width), threads=threads)

    def eval_angles(
        self, theta_i: Any, phi_i: Any, theta_o: Any, phi_o: Any, width: int | None = None, threads: int = 0
    ) -> np.ndarray:
        """BRDF values for angles in radians (broadcast together); shape (*broadcast, channels)."""
        ti, pi, to, po = np.broadcast_arrays(
            *(np.asarray(v, dtype=np.float64) for v in (theta_i, phi_i, theta_o, phi_o))
        )
        shape = ti.shape
        wi = angles_to_directions(ti.ravel(), pi.ravel())
        wo = angles_to_directions(to.ravel(), po.ravel())
        out = self.eval(wi, wo, width=width, threads=threads)
        return out.reshape(*shape, self.channels)

    # --- description
    @property
    def parametrization(self) -> str:
        return self._table.parametrization

    @property
    def channels(self) -> int:
        return self._table.channels

    @property
    def channel_kind(self) -> str:
        return self._table.channel_kind

    @property
    def axes(self) -> list[np.ndarray]:
        return list(self._table.axes)

    @property
    def axis_names(self) -> list[str]:
        return list(self._table.axis_names)

    @property
    def values(self) -> np.ndarray:
        return self._table.values

    @property
    def valid(self) -> np.ndarray | None:
        return self._table.valid

    @property
    def wavelengths(self) -> np.ndarray | None:
        return self._table.wavelengths

    @property
    def table(self) -> _core.Table:
        return self._table

    def info(self) -> dict[str, Any]:
        """A JSON-ready summary: format, grid, channels, value range, missing data, provenance."""
        values = self._table.values
        valid = self._table.valid
        measured = values if valid is None else values[valid.astype(bool)]
        axes = []
        for name, knots in zip(self._table.axis_names, self._table.axes):
            steps = np.diff(knots.astype(np.float64))
            axes.append(
                {
                    "name": name,
                    "knots": int(knots.size),
                    "min_deg": float(np.degrees(knots[0])),
                    "max_deg": float(np.degrees(knots[-1])),
                    "min_step_deg": float(np.degrees(steps.min())),
                    "max_step_deg": float(np.degrees(steps.max())),
                    "uniform": bool(np.allclose(steps, steps[0], rtol=1e-4)),
                }
            )
        sym = self._table.symmetry
        return {
            "source": self.source,
            "format": self.source_format,
            "parametrization": self.parametrization,
            "axes": axes,
            "channels": self.channels,
            "channel_kind": self.channel_kind,
            "wavelengths_nm": None if self.wavelengths is None else [float(w) for w in self.wavelengths],
            "symmetry": [n for bit, n in ((1, "reciprocity"), (2, "phi_mirror")) if sym & bit],
            "grid_points": int(self._table.point_count),
            "missing_points": int(self._table.missing_count),
            "units": self._table.units,
            "value_min": [float(v) for v in measured.reshape(-1, self.channels).min(axis=0)] if measured.size else [],
            "value_max": [float(v) for v in measured.reshape(-1, self.channels).max(axis=0)] if measured.size else [],
            "value_mean": [float(v) for v in measured.reshape(-1, self.channels).mean(axis=0)] if measured.size else [],
            "provenance": self._table.provenance,
        }

    # --- output
    def save(self, path: str | os.PathLike) -> None:
        """Writes the table as .ptab (atomically: a temporary file, then a rename)."""
        path = os.fspath(path)
        if not path.endswith(".ptab"):
            raise ValueError(f"{path}: Patina writes its native format only; use a .ptab file name")
        if is_utf8(path):
            _core.write_ptab(self._table, path)
            return
        # the engine takes UTF-8 names only: write a UTF-8-named temporary file in the same folder
        # (reached through a UTF-8 alias of the folder when its own name is not), then rename it
        try:
            with engine_path(os.path.dirname(os.path.abspath(path))) as folder:
                fd, temporary = tempfile.mkstemp(prefix=".patina-save.", suffix=".ptab", dir=folder)
                os.close(fd)
                try:
                    _core.write_ptab(self._table, temporary)
                    os.replace(temporary, path)
                except BaseException:
                    with contextlib.suppress(OSError):
                        os.unlink(temporary)
                    raise
        except OSError as e:  # named as given, not the temporary file (and no "[Errno n]")
            named = OSError(f"{printable(path)}: cannot write: {e.strerror or e}")
            named.errno = e.errno
            raise named from None

    def __repr__(self) -> str:
        dims = "x".join(str(a.size) for a in self._table.axes)
        return f"<Brdf {self.parametrization} {dims} {self.channel_kind}[{self.channels}] from {self.source!r}>"
