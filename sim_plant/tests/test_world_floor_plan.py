"""World ``floor_plan``: a room drawn as a picture. Its dark pixels are solid; their edges
with the floor, and the picture's edges, are the walls (merged into straight runs), at the
picture's scale, (0, 0) at its bottom-left corner; an SVG drawing works as a PNG does; a
start on a wall, a missing scale or a picture of noise is refused by name."""

import numpy as np
import pytest
from PIL import Image

from sim_plant.catalogue.assembly import assemble
from sim_plant.catalogue.base import PartsError

MOTORS = [
    {"kind": "dc_motor", "name": f"motor_{s}", "drives": side, "time_constant_ms": 0}
    for s, side in (("l", "left"), ("r", "right"))
]


def plan(tmp_path, picture="room.png", **world):
    options = {"picture": picture, "mm_per_px": 10.0, "start_pose": [0.1, 0.25, 0.0], **world}
    table = {"body": "differential", "world": "floor_plan", "world_options": options, "parts": MOTORS}
    return assemble(table, base=tmp_path)


def room(path, boxes=((40, 20, 60, 30),), size=(100, 50)):
    """A white picture (10 mm a pixel: 1 x 0.5 m) with black boxes (left, top, right, bottom pixels)."""
    image = Image.new("L", size, 255)
    for box in boxes:
        image.paste(0, box)
    image.save(path)


def test_a_dark_box_and_the_pictures_edges_are_the_walls_at_the_pictures_scale(tmp_path):
    room(tmp_path / "room.png")  # the box: columns 40..59, rows 20..29: x 0.4..0.6 m, y 0.2..0.3 m
    plant = plan(tmp_path)
    world = plant.world
    walls = sorted(tuple(round(v, 9) for v in s) for s in world.segments())
    box = [(0.4, 0.2, 0.6, 0.2), (0.4, 0.3, 0.4, 0.2), (0.4, 0.3, 0.6, 0.3), (0.6, 0.3, 0.6, 0.2)]
    outer = [(0.0, 0.0, 1.0, 0.0), (0.0, 0.5, 0.0, 0.0), (0.0, 0.5, 1.0, 0.5), (1.0, 0.5, 1.0, 0.0)]
    assert walls == sorted(box + outer), f"expected the box's four sides and the picture's four edges: {walls}"
    assert world.name == "floor plan 1 x 0.5 m" and plant.start_pose == (0.1, 0.25, 0.0)
    assert world.ray(0.1, 0.25, 0.0)[0] == pytest.approx(0.3), "a ray along x meets the box at x = 0.4 m"
    assert world.ray(0.1, 0.1, 0.0)[0] == pytest.approx(0.9), "below the box: the far wall"
    assert world.contains(0.1, 0.25) and not world.contains(0.5, 0.25), "floor is free space, the box is not"


def test_an_l_shaped_wall_is_two_runs_not_a_segment_a_pixel(tmp_path):
    room(tmp_path / "room.png", boxes=[(20, 10, 80, 12), (20, 10, 22, 40)])
    walls = plan(tmp_path).world.segments()
    assert len(walls) == 4 + 6, f"expected the L's six sides and the four edges, got {len(walls)}: {walls}"


SVG = """<svg xmlns="http://www.w3.org/2000/svg" width="1000" height="500">
  <rect width="1000" height="500" fill="white"/>
  <rect x="400" y="200" width="200" height="100" fill="black"/>
</svg>"""


def test_an_svg_room_is_read_as_its_drawing_at_a_millimetre_a_pixel(tmp_path):
    (tmp_path / "room.svg").write_text(SVG)  # 1000 x 500 units at 1 mm a unit: the same room as room()'s
    world = plan(tmp_path, picture="room.svg", mm_per_px=1.0).world
    assert world.ray(0.1, 0.25, 0.0)[0] == pytest.approx(0.3, abs=0.002), "the box's near side at x = 0.4 m"
    assert len(world.walls) == 8, f"expected the box's sides and the edges, got {len(world.walls)} walls"


@pytest.mark.parametrize(
    ("world", "message"),
    [
        (
            {"start_pose": [0.5, 0.25, 0.0]},
            r"\[world\] start_pose: \[0\.5, 0\.25, 0\.0\] is not on the drawing's floor",
        ),
        ({"start_pose": [1.5, 0.25, 0.0]}, r"\[world\] start_pose: .* is not on the drawing's floor"),
        ({"mm_per_px": None}, r"\[world\] mm_per_px, width_m: expected the picture's scale"),
        ({"picture": None}, r"\[world\] picture: expected the room's picture"),
        ({"picture": "none.png"}, r"\[world\] picture: cannot read /.*/none\.png \(No such file or directory\)"),
    ],
)
def test_a_start_on_a_wall_a_missing_scale_or_picture_is_refused_by_name(tmp_path, world, message):
    room(tmp_path / "room.png")
    with pytest.raises(PartsError, match=message):
        plan(tmp_path, **world)


def test_a_picture_of_noise_is_refused_with_its_wall_count(tmp_path):
    noise = (np.random.default_rng(1).random((200, 200)) < 0.5).astype(np.uint8) * 255
    Image.fromarray(noise, "L").save(tmp_path / "room.png")
    with pytest.raises(PartsError, match=r"room\.png makes [\d,]+ wall segments, more than 20,000"):
        plan(tmp_path, start_pose=None)
