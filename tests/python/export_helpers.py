"""Materials and fit.json files the export tests share."""

from __future__ import annotations

import json

from patina.export.material import AnalyticMaterial, Coat, Lobe

GGX = AnalyticMaterial("red_plastic", (0.4, 0.1, 0.08), (Lobe("ggx", 0.12, (0.04, 0.045, 0.05)),))
TWO_GGX = AnalyticMaterial(
    "two_lobes", (0.3, 0.2, 0.1), (Lobe("ggx", 0.3, (0.04, 0.05, 0.06)), Lobe("ggx", 0.05, (0.5, 0.6, 0.7)))
)
# two lobes whose principled parts' fixed blend weights (1 - min f0) leave room for the diffuse: exact in Mitsuba
TWO_BRIGHT = AnalyticMaterial(
    "two_bright", (0.2, 0.1, 0.1), (Lobe("ggx", 0.3, (0.6, 0.7, 0.8)), Lobe("ggx", 0.05, (0.7, 0.75, 0.8)))
)
BECKMANN = AnalyticMaterial("beckmann", (0.5, 0.2, 0.1), (Lobe("beckmann", 0.15, (0.04, 0.05, 0.06)),))
COATED = AnalyticMaterial("coated", (0.3, 0.2, 0.1), (Lobe("ggx", 0.3, (0.04, 0.05, 0.06)),), Coat(0.05, 1.6))
LAMBERT_COAT = AnalyticMaterial("lacquer", (0.5, 0.2, 0.1), (), Coat(0.05, 1.5))
SMOOTH_COAT = AnalyticMaterial("smooth_lacquer", (0.5, 0.2, 0.1), (), Coat(0.005, 1.5))  # Mitsuba's plastic: exact
METAL = AnalyticMaterial("gold", (0.0, 0.0, 0.0), (Lobe("ggx", 0.08, (0.95, 0.7, 0.3)),))

GGX_FIT = {
    "model": "ggx+lambert",
    "parameters": {"rho_r": 0.4, "rho_g": 0.1, "rho_b": 0.08, "alpha": 0.12, "f0_r": 0.04, "f0_g": 0.045, "f0_b": 0.05},
}
WARD_FIT = {
    "model": "ward+lambert",
    "parameters": {"rho_r": 0.4, "rho_g": 0.1, "rho_b": 0.08, "alpha": 0.15, "f0_r": 0.05, "f0_g": 0.05, "f0_b": 0.05},
}


def write_json(path, doc) -> str:
    path.write_text(json.dumps(doc))
    return str(path)
