"""A scene's point, spot and goniometric lights as the plan shows them."""

from __future__ import annotations

from patina.lighting.direct import is_delta
from patina.lighting.plan import PlanLuminaire
from patina.scene.types import LuminaireLight, Scene, SpotLight


def plan_luminaires(scene: Scene) -> list[PlanLuminaire]:
    out = []
    for light in scene.lights:
        if not is_delta(light):
            continue
        if isinstance(light, LuminaireLight):
            aim = light.aim
        elif isinstance(light, SpotLight):
            aim = light.direction
        else:
            aim = (0.0, -1.0, 0.0)
        x, y, z = (float(v) for v in light.position)
        out.append(PlanLuminaire(x, z, y, tuple(float(v) for v in aim)))
    return out
