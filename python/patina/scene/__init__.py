"""Scenes: the frozen dataclasses a scene file becomes (types), reading JSON with key paths
(json_reader), reading and checking a scene file (reading), writing it back (writing), the
preview scene built from a table (preview) and the Mitsuba 3 export (mitsuba)."""

from patina.scene.reading import load_scene, parse_scene, with_overrides
from patina.scene.types import Scene
from patina.scene.writing import scene_to_json

__all__ = ["Scene", "load_scene", "parse_scene", "scene_to_json", "with_overrides"]
