"""The `lighting` benchmark group in quick mode: its records well formed, the group registered,
and the exact direct sum it times the same bits at every SIMD width (the width changes the speed
of the candela lookups and shadow packets, never the lux)."""

from __future__ import annotations

import math

import numpy as np

from patina.bench import GROUPS
from patina.bench import lighting as lb
from patina.bench.records import simd_widths
from patina.lighting.direct import direct_illuminance
from patina.lighting.sensors import make_sensors
from patina.render.illuminance import ray_offset
from patina.render.prepare import PreparedScene


def test_quick_group_records(tmp_path, monkeypatch):
    monkeypatch.setenv("PATINA_BENCH_CACHE", str(tmp_path))
    records = lb.bench_lighting(1, quick=True)
    names = {r.name for r in records}
    expected = {f"lighting.direct.sensors_per_s.w{w}" for w in simd_widths()}
    assert names == expected | {"lighting.indirect.vs_path_equal_error"}
    for r in records:
        assert math.isfinite(r.ratio) and r.ratio > 0 and math.isfinite(r.value) and r.value > 0, r
    assert GROUPS["lighting"] is lb.bench_lighting


def test_the_field_is_shadowed_and_width_independent():
    scene, sources = lb.luminaire_field()
    assert len(sources) == 20 and {s.luminaire.photometry.path[-3:] for s in sources} == {"ies", "ldt"}
    prepared = PreparedScene(scene)
    x = np.linspace(-14, 14, 57)
    pts = np.stack([x, np.full_like(x, 0.75), np.full_like(x, -6.0)], axis=1)  # through the balls' row
    sensors = make_sensors(pts, "up", None)
    args = sources, sensors, prepared.accel, ray_offset(prepared)
    lit = direct_illuminance(*args, per_source=True, width=1, threads=1)
    open_sky = direct_illuminance(sources, sensors, None, ray_offset(prepared), per_source=True, width=1)
    assert np.any((open_sky > 0) & (lit == 0))  # some luminaire hidden from some sensor
    for w in simd_widths():
        wide = direct_illuminance(*args, per_source=True, width=w, threads=1)
        assert np.array_equal(wide, lit), w
