"""`patina validate`: can this measured table be trusted?

Checks, each with figures and the worst places (angles in degrees):
- finite: every value finite; `validate(bad=...)` takes the values a reader found unusable
  (NaN, infinite, beyond float32: patina.table.formats.lenient), lists them with their
  place in the file, and the other checks run on the table with those points masked;
- negative: values below zero (physically impossible; measurement offsets);
- axes: angle ranges within the parametrization's domain, how much of it they cover,
  and the largest gap between knots;
- coverage: missing measurements (the table's mask) and the largest run of them. Grid
  points no measurement can reach (a half/difference pair with a direction at or below
  the horizon: about a quarter of a MERL grid, which MERL stores as negative) are
  counted apart as unreachable and are not a problem; holes inside the measurable
  domain are;
- reciprocity: Helmholtz, f(wi, wo) = f(wo, wi), on random direction pairs;
- albedo: directional albedo a(theta_i) = integral of f cos(theta_o) over the
  hemisphere, per channel; above 1 (beyond a tolerance) the table creates energy;
- spikes: grid values far above (or below) all their neighbours, typical of glitches.

Every evaluation goes through the SIMD evaluator (Brdf.eval).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from patina.table.angles import halfdiff_to_directions
from patina.table.brdf import Brdf, angles_to_directions
from patina.table.formats.tabledata import BadValues

# Evaluations run in chunks of at most this many values (pairs x channels): a 4096-channel
# spectral table otherwise asked for 6.4 GB (40 000 reciprocity pairs, 18 432 albedo
# directions, each times 4096 channels, in float64).
VALUE_BUDGET = 1 << 22
MIN_RECIPROCITY_PAIRS = 1000  # the fewest pairs a many-channel table is checked on


@dataclass
class Tolerances:
    """Thresholds that make a finding a problem."""

    reciprocity_p95: float = 0.05  # relative difference at the 95th percentile
    albedo_excess: float = 0.02  # albedo may exceed 1 by this much (quadrature and noise)
    spike_factor: float = 5.0  # a value this many times above (or below) all its neighbours
    negative_fraction: float = 0.0  # any negative value is a problem


@dataclass
class Report:
    source: str
    format: str
    parametrization: str
    checks: dict[str, dict[str, Any]] = field(default_factory=dict)
    problems: list[str] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        return not self.problems

    def as_json(self) -> dict[str, Any]:
        return {
            "file": self.source,
            "format": self.format,
            "parametrization": self.parametrization,
            "ok": self.ok,
            "problems": self.problems,
            "checks": self.checks,
        }


def _deg(x: Any) -> float:
    return round(float(np.degrees(x)), 3)


def _place(brdf: Brdf, index: tuple[int, ...]) -> dict[str, float]:
    """Grid index -> {axis name: knot in degrees}."""
    return {name: _deg(axis[i]) for name, axis, i in zip(brdf.axis_names, brdf.axes, index)}


def check_finite(brdf: Brdf, report: Report, bad: BadValues | None = None) -> None:
    """The reader's unusable values (bad) and any non-finite value left in the table."""
    left = ~np.isfinite(brdf.values)
    count = int(left.sum()) + (bad.count if bad else 0)
    places = list(bad.places) if bad else []
    for idx in np.argwhere(left)[: max(0, BadValues.FIRST - len(places))]:
        index = tuple(int(i) for i in idx)
        places.append({**_place(brdf, index[:-1]), "channel": index[-1], "value": f"{float(brdf.values[index]):g}"})
    report.checks["finite"] = {"non_finite": count, "first": places}
    if count:
        shown = "; ".join(_describe_bad(p) for p in places[:3])
        more = f" (first: {shown})" if shown else ""
        report.problems.append(f"{count} value{'s are' if count > 1 else ' is'} NaN, infinite or beyond float32{more}")


def _describe_bad(place: dict[str, Any]) -> str:
    where = place.get("where", "")
    rest = ", ".join(f"{k} {v}" for k, v in place.items() if k not in ("where", "value"))
    return f"{place['value']} at {where + (', ' if where and rest else '')}{rest}"


def check_negative(brdf: Brdf, report: Report, tol: Tolerances) -> None:
    values = brdf.values
    negative = values < 0
    count = int(negative.sum())
    worst = []
    if count:
        flat = np.argsort(values, axis=None)[: min(count, 5)]
        for f in flat:
            idx = np.unravel_index(f, values.shape)
            worst.append({**_place(brdf, idx[:-1]), "channel": int(idx[-1]), "value": float(values[idx])})
    fraction = count / values.size
    report.checks["negative"] = {"count": count, "fraction": fraction, "minimum": float(values.min()), "worst": worst}
    if fraction > tol.negative_fraction:
        report.problems.append(f"{count} negative values (minimum {values.min():.4g})")


# Each parametrization's axes: their domain in radians and what they should span.
_DOMAINS = {
    "theta": (0.0, math.pi / 2),
    "phi_d": (0.0, math.pi),
    "phi_i": (0.0, 2 * math.pi),
    "phi_o": (0.0, 2 * math.pi),
}


def check_axes(brdf: Brdf, report: Report) -> None:
    axes = []
    for name, knots in zip(brdf.axis_names, brdf.axes):
        k = knots.astype(np.float64)
        lo, hi = _DOMAINS["theta"] if name.startswith("theta") else _DOMAINS[name]
        if name == "phi_d" and brdf.parametrization == "halfdiff" and "phi_mirror" in brdf.info()["symmetry"]:
            hi = math.pi / 2
        elif name == "phi_d" and brdf.parametrization == "halfdiff" and not brdf.info()["symmetry"]:
            lo = -math.pi  # nothing folded: the kernels look phi_d up in (-pi, pi] (brdf/eval.h)
        tol = 1e-4
        outside = bool(k[0] < lo - tol or k[-1] > hi + tol)
        span = (min(k[-1], hi) - max(k[0], lo)) / (hi - lo)
        steps = np.diff(k)
        entry = {
            "name": name,
            "knots": int(k.size),
            "from_deg": _deg(k[0]),
            "to_deg": _deg(k[-1]),
            "domain_deg": [_deg(lo), _deg(hi)],
            "covers": round(float(span), 4),
            "largest_gap_deg": _deg(steps.max()),
            "outside_domain": outside,
        }
        axes.append(entry)
        if outside:
            report.problems.append(
                f"axis {name} spans {entry['from_deg']}..{entry['to_deg']} deg, outside {entry['domain_deg']}"
            )
    report.checks["axes"] = {"axes": axes}


# A grid point whose cell reaches within this of the horizon (elevation, radians) counts as
# at the horizon: MERL marks its cells from its own binning, and a knot is a cell's corner.
HORIZON_TOLERANCE = 1e-6


def unreachable_points(brdf: Brdf) -> np.ndarray | None:
    """Grid points (grid-shaped bool) no measurement can reach, or None when there are none:
    for half/difference angles those with wi or wo at or below the horizon, the knot's cell
    (to the next knot on each axis) included, since a cell that reaches the horizon is
    MERL's below-horizon bin. Isotropic and anisotropic grids have theta <= 90 deg and
    reach everywhere."""
    if brdf.parametrization != "halfdiff":
        return None
    axes = [a.astype(np.float64) for a in brdf.axes]
    far = [np.append(a[1:], a[-1]) for a in axes]
    lowest = None
    for corner in np.ndindex(2, 2, 2):  # the cell's 8 corners
        grids = np.meshgrid(*[far[k] if c else axes[k] for k, c in enumerate(corner)], indexing="ij")
        wi, wo = halfdiff_to_directions(*grids)
        z = np.minimum(wi[:, 2], wo[:, 2])
        lowest = z if lowest is None else np.minimum(lowest, z)
    assert lowest is not None
    out = (lowest <= HORIZON_TOLERANCE).reshape([a.size for a in axes])
    return out if out.any() else None


def check_coverage(
    brdf: Brdf, report: Report, bad: BadValues | None = None, unreachable: np.ndarray | None = None
) -> None:
    """unreachable: unreachable_points(brdf)."""
    valid = brdf.valid
    total = int(np.prod([a.size for a in brdf.axes]))
    beyond = int(unreachable.sum()) if unreachable is not None else 0
    if valid is None:
        report.checks["coverage"] = {
            "missing": 0,
            "fraction_missing": 0.0,
            "unreachable": beyond,
            "unreachable_missing": 0,
        }
        return
    missing = valid == 0
    if bad is not None and bad.points is not None and bad.points.shape == missing.shape:
        missing &= ~bad.points  # reported by check_finite
    unreachable_missing = 0
    if unreachable is not None:
        unreachable_missing = int((missing & unreachable).sum())
        missing &= ~unreachable
    count = int(missing.sum())
    reachable = total - beyond
    # the longest run of missing knots along the last axis, as a measure of the largest hole
    runs = 0
    flat = missing.reshape(-1, missing.shape[-1])
    for row in flat:
        if row.any():
            padded = np.concatenate([[0], row.astype(np.int8), [0]])
            d = np.diff(padded)
            runs = max(runs, int((np.nonzero(d == -1)[0] - np.nonzero(d == 1)[0]).max()))
    first = [_place(brdf, tuple(int(i) for i in idx)) for idx in np.argwhere(missing)[:5]]
    report.checks["coverage"] = {
        "missing": count,
        "fraction_missing": count / max(reachable, 1),
        "longest_missing_run": runs,
        "first_missing": first,
        "unreachable": beyond,
        "unreachable_missing": unreachable_missing,
    }
    if count:
        report.problems.append(
            f"{count} of {reachable} measurable grid points are missing ({100 * count / max(reachable, 1):.2f}%)"
        )


def _hemisphere(n: int, rng: np.random.Generator, max_theta: float) -> np.ndarray:
    z = rng.uniform(math.cos(max_theta), 1.0, n)
    phi = rng.uniform(0, 2 * math.pi, n)
    r = np.sqrt(1 - z * z)
    return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1).astype(np.float32)


def check_reciprocity(brdf: Brdf, report: Report, tol: Tolerances, samples: int = 40_000) -> None:
    """Random pairs away from grazing (theta < 80 deg); relative difference per channel.
    Tables with many channels get fewer pairs (VALUE_BUDGET values in all, at least
    MIN_RECIPROCITY_PAIRS pairs): the percentiles are over pairs times channels."""
    samples = min(samples, max(MIN_RECIPROCITY_PAIRS, VALUE_BUDGET // brdf.channels))
    rng = np.random.default_rng(7)
    wi = _hemisphere(samples, rng, math.radians(80))
    wo = _hemisphere(samples, rng, math.radians(80))
    a = brdf.eval(wi, wo).astype(np.float64)
    b = brdf.eval(wo, wi).astype(np.float64)
    floor = max(1e-3 * float(np.median(np.abs(brdf.values))), 1e-12)
    rel = np.abs(a - b) / np.maximum(0.5 * (np.abs(a) + np.abs(b)), floor)
    worst_pair = np.argsort(rel.max(axis=1))[::-1][:5]
    theta = np.degrees(np.arccos(np.clip(wi[:, 2], -1, 1)))
    phi = np.degrees(np.arctan2(wi[:, 1], wi[:, 0]))
    theta_o = np.degrees(np.arccos(np.clip(wo[:, 2], -1, 1)))
    phi_o = np.degrees(np.arctan2(wo[:, 1], wo[:, 0]))
    worst = [
        {
            "wi_deg": [round(float(theta[i]), 2), round(float(phi[i]), 2)],
            "wo_deg": [round(float(theta_o[i]), 2), round(float(phi_o[i]), 2)],
            "f_wi_wo": [float(v) for v in a[i]],
            "f_wo_wi": [float(v) for v in b[i]],
            "relative_difference": float(rel[i].max()),
        }
        for i in worst_pair
    ]
    p95 = float(np.percentile(rel, 95))
    report.checks["reciprocity"] = {
        "pairs": samples,
        "median": float(np.median(rel)),
        "p95": p95,
        "max": float(rel.max()),
        "worst": worst,
    }
    swapped_knots = _swapped_pairs_are_knots(brdf)
    if swapped_knots is not None:
        report.checks["reciprocity"]["same_incident_and_outgoing_knots"] = swapped_knots
    if p95 > tol.reciprocity_p95:
        why = (
            " (the incident and outgoing knots differ: between them a lobe narrower than the spacing "
            "is interpolated differently on each side, even when the values at the knots are reciprocal)"
            if swapped_knots is False
            else ""
        )
        report.problems.append(
            f"not reciprocal: f(wi, wo) and f(wo, wi) differ by {100 * p95:.1f}% at the 95th percentile{why}"
        )


def _swapped_pairs_are_knots(brdf: Brdf) -> bool | None:
    """For an anisotropic table, whether (theta_o, phi_o) has the same knots as (theta_i,
    phi_i), which makes multilinear interpolation symmetric under swapping wi and wo; None
    for the other parametrizations (their grids are symmetric by construction or not at all)."""
    if brdf.parametrization != "anisotropic":
        return None
    ti, pi, to, po = (np.asarray(a, dtype=np.float64) for a in brdf.axes)
    return bool(ti.shape == to.shape and pi.shape == po.shape and np.allclose(ti, to) and np.allclose(pi, po))


def directional_albedo(
    brdf: Brdf, theta_i: np.ndarray, phi_i: float = 0.0, n_mu: int = 96, n_phi: int = 192
) -> np.ndarray:
    """a(theta_i) per channel: Gauss-Legendre in cos(theta_o) times uniform phi_o; (len(theta_i), channels)."""
    x, w = np.polynomial.legendre.leggauss(n_mu)
    mu = 0.5 * (x + 1.0)  # cos(theta_o) in (0, 1)
    w_mu = 0.5 * w
    phi = (np.arange(n_phi) + 0.5) * (2 * math.pi / n_phi)
    m, p = np.meshgrid(mu, phi, indexing="ij")
    weight = (w_mu[:, None] * (2 * math.pi / n_phi) * m).ravel()  # includes the cosine
    wo = angles_to_directions(np.arccos(m.ravel()), p.ravel())
    out = np.zeros((len(theta_i), brdf.channels))
    step = max(1, VALUE_BUDGET // brdf.channels)  # directions per evaluation: bounded memory
    for k, t in enumerate(theta_i):
        wi = angles_to_directions(t, phi_i)
        for start in range(0, len(wo), step):
            part = wo[start : start + step]
            f = brdf.eval(np.broadcast_to(wi, part.shape), part).astype(np.float64)
            out[k] += weight[start : start + step] @ f
    return out


def check_albedo(brdf: Brdf, report: Report, tol: Tolerances) -> None:
    theta_i = np.radians(np.arange(0.0, 86.0, 5.0))
    phis = [0.0] if brdf.parametrization != "anisotropic" else [0.0, math.pi / 4, math.pi / 2, 3 * math.pi / 4]
    rows = []
    worst = 0.0
    worst_at = None
    for phi_i in phis:
        albedo = directional_albedo(brdf, theta_i, phi_i)
        for t, a in zip(theta_i, albedo):
            rows.append({"theta_i_deg": _deg(t), "phi_i_deg": _deg(phi_i), "albedo": [round(float(v), 5) for v in a]})
            if a.max() > worst:
                worst, worst_at = float(a.max()), (t, phi_i)
    report.checks["albedo"] = {"per_incidence": rows, "max": worst, "tolerance": tol.albedo_excess}
    if worst > 1.0 + tol.albedo_excess and worst_at is not None:
        report.problems.append(
            f"directional albedo {worst:.3f} > 1 at theta_i = {_deg(worst_at[0])} deg: the table creates energy"
        )


def check_spikes(brdf: Brdf, report: Report, tol: Tolerances, unreachable: np.ndarray | None = None) -> None:
    """Points more than spike_factor times above every neighbour (or below every one);
    unreachable points are neither judged nor neighbours (a knot on the horizon holds a
    grazing value divided by a cosine near 0)."""
    v = brdf.values.astype(np.float64)
    valid = brdf.valid
    measured = np.ones(v.shape[:-1], bool) if valid is None else valid.astype(bool)
    if unreachable is not None:
        measured &= ~unreachable
    dims = v.ndim - 1
    hi = np.full(v.shape, -np.inf)
    lo = np.full(v.shape, np.inf)
    for a in range(dims):
        for shift in (1, -1):
            nb = np.roll(v, shift, axis=a)
            ok = np.roll(measured, shift, axis=a)
            edge = [slice(None)] * dims
            edge[a] = slice(0, 1) if shift == 1 else slice(-1, None)
            ok = ok.copy()
            ok[tuple(edge)] = False  # no wrap-around neighbours
            nb = np.where(ok[..., None], nb, np.nan)
            hi = np.fmax(hi, nb)
            lo = np.fmin(lo, nb)
    scale = max(float(np.median(np.abs(v[measured]))) if measured.any() else 0.0, 1e-12)
    with np.errstate(invalid="ignore"):
        up = (v > tol.spike_factor * np.maximum(hi, 1e-3 * scale)) & np.isfinite(hi)
        down = (v * tol.spike_factor < lo) & (lo > 1e-3 * scale) & np.isfinite(lo)
    spikes = (up | down) & measured[..., None]
    places = np.argwhere(spikes)
    worst = []
    for row in places[:8]:
        idx = tuple(int(i) for i in row)
        worst.append(
            {
                **_place(brdf, idx[:-1]),
                "channel": idx[-1],
                "value": float(v[idx]),
                "neighbours": [float(lo[idx]), float(hi[idx])],
            }
        )
    report.checks["spikes"] = {"count": len(places), "factor": tol.spike_factor, "first": worst}
    if len(places):
        report.problems.append(
            f"{len(places)} isolated spikes or dips (more than {tol.spike_factor:g}x off every neighbour)"
        )


def validate(brdf: Brdf, tol: Tolerances | None = None, bad: BadValues | None = None) -> Report:
    """Every check; `bad`: the values the reader masked (read_reporting_bad_values)."""
    tol = tol or Tolerances()
    report = Report(brdf.source, brdf.source_format, brdf.parametrization)
    check_finite(brdf, report, bad)
    check_negative(brdf, report, tol)
    check_axes(brdf, report)
    unreachable = unreachable_points(brdf)
    check_coverage(brdf, report, bad, unreachable)
    check_reciprocity(brdf, report, tol)
    check_albedo(brdf, report, tol)
    check_spikes(brdf, report, tol, unreachable)
    return report


def format_report(report: Report) -> str:
    c = report.checks
    lines = [f"{report.source}  ({report.format}, {report.parametrization})"]

    def row(name: str, ok: bool, text: str) -> None:
        lines.append(f"  {'ok  ' if ok else 'FAIL'}  {name:<12} {text}")

    fin = c["finite"]
    row("finite", fin["non_finite"] == 0, f"{fin['non_finite']} NaN, infinite or beyond-float32 values")
    for p in fin["first"][:5]:
        lines.append(f"          {_describe_bad(p)}")
    neg = c["negative"]
    row("negative", neg["count"] == 0, f"{neg['count']} negative values (minimum {neg['minimum']:.4g})")
    for a in c["axes"]["axes"]:
        row(
            "axis",
            not a["outside_domain"],
            f"{a['name']:<8} {a['knots']:>4} knots {a['from_deg']}..{a['to_deg']} deg, covers "
            f"{100 * a['covers']:.0f}% of {a['domain_deg']}, largest gap {a['largest_gap_deg']} deg",
        )
    cov = c["coverage"]
    row(
        "coverage",
        cov["missing"] == 0,
        f"{cov['missing']} missing points ({100 * cov['fraction_missing']:.2f}% of the measurable grid)",
    )
    if cov["unreachable"]:
        lines.append(
            f"          {cov['unreachable']} grid points lie at or below the horizon (unreachable, "
            f"{cov['unreachable_missing']} of them marked missing): not missing data"
        )
    rec = c["reciprocity"]
    row(
        "reciprocity",
        not any(p.startswith("not reciprocal") for p in report.problems),
        f"relative |f(wi,wo) - f(wo,wi)|: median {rec['median']:.2e}, 95% {rec['p95']:.2e}, max {rec['max']:.2e}",
    )
    alb = c["albedo"]
    row("albedo", alb["max"] <= 1 + alb["tolerance"], f"max directional albedo {alb['max']:.4f}")
    rows = alb["per_incidence"]
    if report.parametrization == "anisotropic":  # a few incidences at each phi_i, which each row names
        shown = [r for r in rows if r["theta_i_deg"] in (0.0, 30.0, 60.0)]
    else:
        shown = rows[:: max(1, len(rows) // 6)]
    for r in shown:
        at = f"theta_i {r['theta_i_deg']:>5} deg" + (
            f", phi_i {r['phi_i_deg']:>5} deg" if report.parametrization == "anisotropic" else ""
        )
        lines.append(f"          {at}: " + " ".join(f"{v:.4f}" for v in r["albedo"][:3]))
    sp = c["spikes"]
    row("spikes", sp["count"] == 0, f"{sp['count']} isolated spikes or dips")
    lines.append("result: " + ("clean" if report.ok else f"{len(report.problems)} problem(s)"))
    lines += [f"  - {p}" for p in report.problems]
    return "\n".join(lines)
