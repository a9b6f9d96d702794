"""Scene files: the shipped arena loads; malformed files name the offending key."""
import os

import pytest

from epuck_vrep_compat.scene.placement import place_robots
from epuck_vrep_compat.scene.scene_file import SceneError, load_scene, parse_scene
from repo import REPO

WORLDS = os.path.join(REPO, "worlds")


def test_default_arena_loads():
    scene = load_scene(os.path.join(WORLDS, "arena.yaml"))
    assert scene.arena.size_m == (1.0, 1.0)
    assert len(scene.obstacles) >= 3
    assert len(scene.robots) >= 2


def test_missing_file_is_a_scene_error(tmp_path):
    with pytest.raises(SceneError, match="cannot read"):
        load_scene(str(tmp_path / "nope.yaml"))


def test_invalid_yaml_is_a_scene_error(tmp_path):
    p = tmp_path / "bad.yaml"
    p.write_text("arena: [1, 2\n")
    with pytest.raises(SceneError, match="not valid YAML"):
        load_scene(str(p))


@pytest.mark.parametrize("data, key", [
    ({"arena": {"size_m": [1.0]}}, "size_m"),
    ({"arena": {"size_m": [1.0, -1.0]}}, "size_m"),
    ({"arena": {"wall_height_m": float("nan")}}, "wall_height_m"),
    ({"obstacles": [{"shape": "cone", "position_m": [0, 0]}]}, "shape"),
    ({"obstacles": [{"shape": "box"}]}, "position_m"),
    ({"robots": [{"position_m": [0, "x"]}]}, "position_m"),
    ({"robots": [{"position": [0, 0]}]}, "unknown key"),
    ({"arenas": {}}, "unknown key"),
    ({"obstacles": [{"shape": "box", "position_m": [0, 0], "color": [2, 0, 0]}]}, "color"),
])
def test_malformed_scene_names_the_key(data, key):
    with pytest.raises(SceneError, match=key):
        parse_scene(data)


def test_placement_fills_grid_avoiding_obstacles():
    scene = load_scene(os.path.join(WORLDS, "arena.yaml"))
    poses = place_robots(scene, 30, 0.037)
    assert len(poses) == 30
    assert poses[:2] == [(r.position_m[0], r.position_m[1], r.yaw_rad) for r in scene.robots[:2]]
    for i, (x, y, _) in enumerate(poses):
        assert abs(x) < 0.5 - 0.037 and abs(y) < 0.5 - 0.037
        for (x2, y2, _) in poses[i + 1:]:
            assert (x - x2) ** 2 + (y - y2) ** 2 >= (2 * 0.037) ** 2


def test_too_many_robots_is_an_error():
    scene = parse_scene({"arena": {"size_m": [0.3, 0.3]}})
    with pytest.raises(SceneError, match="fit"):
        place_robots(scene, 50, 0.037)
