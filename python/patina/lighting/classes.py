"""The lighting classes of EN 13201-2:2015 and the requirements of EN 12464-1, checked pass /
fail with the margin (how far above a minimum or below a maximum the figure is, relative).

Road classes (EN 13201-2:2015, tables 1 to 3; maintained values):
- M1-M6 (motorised traffic, luminance): L_av minimum (cd/m^2), U0 minimum, U_l minimum,
  TI maximum (%), EIR minimum.
- C0-C5 (conflict areas, illuminance): E_av minimum (lx), U0 minimum.
- P1-P6 (pedestrians and low speed): E_av minimum (lx), E_min minimum (lx).
Indoor (EN 12464-1): the user's Em minimum (lx), U0 minimum, UGR_L maximum and Ra minimum.
"""

from __future__ import annotations

from dataclasses import dataclass

from patina.errors import FormatError

# name: {figure: (kind, limit)}; kind "min": the figure must be at least the limit
ROAD_CLASSES: dict[str, dict[str, tuple[str, float]]] = {
    **{
        f"M{i + 1}": {
            "L_av": ("min", lav),
            "U0": ("min", u0),
            "Ul": ("min", ul),
            "TI": ("max", ti),
            "EIR": ("min", eir),
        }
        for i, (lav, u0, ul, ti, eir) in enumerate(
            [
                (2.0, 0.40, 0.70, 10, 0.35),
                (1.5, 0.40, 0.70, 10, 0.35),
                (1.0, 0.40, 0.60, 15, 0.30),
                (0.75, 0.40, 0.60, 15, 0.30),
                (0.50, 0.35, 0.40, 15, 0.30),
                (0.30, 0.35, 0.40, 20, 0.30),
            ]
        )
    },
    **{f"C{i}": {"E_av": ("min", e), "U0_E": ("min", 0.40)} for i, e in enumerate([50.0, 30.0, 20.0, 15.0, 10.0, 7.5])},
    **{
        f"P{i + 1}": {"E_av": ("min", e), "E_min": ("min", emin)}
        for i, (e, emin) in enumerate([(15.0, 3.0), (10.0, 2.0), (7.5, 1.5), (5.0, 1.0), (3.0, 0.6), (2.0, 0.4)])
    },
}
INDOOR_FIGURES = {"Em": "min", "U0": "min", "UGR": "max", "Ra": "min"}


@dataclass(frozen=True)
class Check:
    figure: str
    value: float | None
    kind: str  # "min" or "max"
    limit: float

    @property
    def passed(self) -> bool | None:
        if self.value is None:
            return None
        return self.value >= self.limit if self.kind == "min" else self.value <= self.limit

    @property
    def margin(self) -> float | None:
        """Relative: positive when passed (0.1: 10 % to spare), negative when failed."""
        if self.value is None or self.limit == 0:
            return None
        m = (self.value - self.limit) / self.limit
        return m if self.kind == "min" else -m

    def as_json(self) -> dict:
        return {
            "figure": self.figure,
            "value": self.value,
            "requirement": f"{'>=' if self.kind == 'min' else '<='} {self.limit:g}",
            "pass": self.passed,
            "margin": self.margin,
        }


def road_class(name: str, option: str = "--class") -> dict[str, tuple[str, float]]:
    key = name.strip().upper()
    if key not in ROAD_CLASSES:
        raise FormatError("command line", option, f"no class '{name}' in EN 13201-2 (M1-M6, C0-C5, P1-P6)")
    return ROAD_CLASSES[key]


def check(requirements: dict[str, tuple[str, float]], figures: dict[str, float | None]) -> list[Check]:
    return [Check(f, figures.get(f), kind, limit) for f, (kind, limit) in requirements.items()]


def indoor_requirements(given: dict[str, float], where: str) -> dict[str, tuple[str, float]]:
    """EN 12464-1 requirements the user gives ({"Em": 500, "U0": 0.6, "UGR": 19, "Ra": 80})."""
    out = {}
    for key, value in given.items():
        if key not in INDOOR_FIGURES:
            raise FormatError(
                where, f"requirements.{key}", f"not an EN 12464-1 requirement (one of {', '.join(INDOOR_FIGURES)})"
            )
        if not isinstance(value, int | float) or isinstance(value, bool) or not value >= 0:
            raise FormatError(where, f"requirements.{key}", f"expected a number >= 0, got {value!r}")
        out[key] = (INDOOR_FIGURES[key], float(value))
    return out
