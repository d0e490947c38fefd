"""World ``line_course``: the floor drawn as a picture. Its x runs right along the picture's
bottom edge and y up it, at its scale; line sensors (analog, digital) and QTR channels see
its darkness, bilinear between pixel centres or the nearest pixel's; a picture that is
missing, unreadable or without a scale is refused by name."""

import pytest
from PIL import Image

from sim_plant.catalogue.assembly import assemble
from sim_plant.catalogue.base import PartsError
from sim_plant.catalogue.qtr import RELEASED

MOTORS = [
    {"kind": "dc_motor", "name": f"motor_{s}", "drives": side, "time_constant_ms": 0}
    for s, side in (("l", "left"), ("r", "right"))
]
W, H = 100, 50  # pixels; at 10 mm a pixel: 1.0 x 0.5 m


def picture(path, mode="L", paint=None):
    """A white W x H picture with a black block over its top-left quarter (columns 0..49,
    rows 0..24: x 0..0.5 m, y 0.25..0.5 m at 10 mm a pixel), and ``paint`` ((box, colour)) over it."""
    white = {"L": 255, "RGB": (255, 255, 255), "RGBA": (255, 255, 255, 255)}[mode]
    black = {"L": 0, "RGB": (0, 0, 0), "RGBA": (0, 0, 0, 255)}[mode]
    image = Image.new(mode, (W, H), white)
    image.paste(black, (0, 0, 50, 25))
    for box, colour in paint or ():
        image.paste(colour, box)
    image.save(path)
    return path


def course(tmp_path, parts=(), *, world=None, **body):
    options = {"picture": "floor.png", "mm_per_px": 10.0, "start_pose": [0.75, 0.1, 0.0], **(world or {})}
    table = {"body": "differential", "world": "line_course", "world_options": options, **body}
    return assemble({**table, "parts": [*MOTORS, *parts]}, base=tmp_path)


def floor_of(tmp_path, **world):
    return course(tmp_path, world=world).world.floor


def test_the_picture_lies_with_its_bottom_left_corner_at_the_origin_at_its_scale(tmp_path):
    picture(tmp_path / "floor.png")
    plant = course(tmp_path)
    floor = plant.world.floor
    assert plant.world.name == "line course 1 x 0.5 m" and plant.world.bounds == (0.0, 0.0, 1.0, 0.5)
    assert floor.darkness(0.1, 0.4) == 1.0, "the top-left quarter is black"
    assert floor.darkness(0.1, 0.1) == floor.darkness(0.9, 0.4) == 0.0, "bottom-left and top-right white"
    assert floor.darkness(1.2, 0.4) == floor.darkness(-0.1, 0.4) == 0.0, "off the picture: white"
    assert plant.start_pose == (0.75, 0.1, 0.0)
    by_width = floor_of(tmp_path, mm_per_px=None, width_m=2.0)
    assert by_width.size_m == (2.0, 1.0) and by_width.darkness(0.2, 0.8) == 1.0, "width_m: 20 mm a pixel"
    assert course(tmp_path, world={"start_pose": None}).start_pose == (0.5, 0.25, 0.0), "the centre by default"


def test_bilinear_darkness_ramps_across_an_edge_over_a_pixel_and_nearest_steps(tmp_path):
    picture(tmp_path / "floor.png")  # the block's right edge at x = 0.5 m, between pixels 49 and 50
    bilinear, nearest = floor_of(tmp_path), floor_of(tmp_path, sample="nearest")
    y = 0.4
    assert [round(bilinear.darkness(x, y), 3) for x in (0.494, 0.495, 0.4975, 0.5, 0.5025, 0.505, 0.51)] == [
        1.0,
        1.0,
        0.75,
        0.5,
        0.25,
        0.0,
        0.0,
    ], "from pixel 49's centre (0.495 m) to pixel 50's (0.505 m) in proportion"
    assert [nearest.darkness(x, y) for x in (0.4975, 0.4999, 0.5, 0.5025)] == [1.0, 1.0, 0.0, 0.0]


def test_grey_colour_and_transparency_are_their_luminance_on_white_paper(tmp_path):
    grey, red = ((60, 10, 70, 20), (128, 128, 128)), ((70, 10, 80, 20), (255, 0, 0))
    picture(tmp_path / "floor.png", "RGB", [grey, red])
    floor = floor_of(tmp_path, sample="nearest")
    assert floor.darkness(0.65, 0.35) == pytest.approx(1 - 128 / 255), "grey: half dark"
    assert floor.darkness(0.75, 0.35) == pytest.approx(1 - 76 / 255), "red: its luminance (ITU-R 601-2, Pillow's L)"
    picture(tmp_path / "floor.png", "RGBA", [((60, 10, 70, 20), (0, 0, 0, 0))])
    assert floor_of(tmp_path).darkness(0.65, 0.35) == 0.0, "transparent: the white paper under it"


def test_line_sensors_read_the_picture_in_proportion_and_digital_ones_flip_at_half(tmp_path):
    picture(tmp_path / "floor.png", paint=[((60, 10, 70, 20), 128)])  # grey around (0.65, 0.35)
    offsets = [[0.0, 0.0], [-0.1, 0.0], [-0.45, 0.05]]  # at (0.75, 0.35): white, grey, black
    line = {"kind": "line_sensor", "name": "line", "offsets_m": offsets}
    comparator = {**line, "name": "comp", "output": "digital"}
    plant = course(tmp_path, [line, comparator], world={"start_pose": [0.75, 0.35, 0.0]})
    grey = 6000 + (1 - 128 / 255) * (58000 - 6000)
    assert [plant.output(f"line.{i}") for i in range(3)] == [6000, round(grey), 58000], "in proportion"
    assert [plant.output(f"comp.{i}") for i in range(3)] == [0, 0, 1], "a comparator: 1 where more than half dark"
    assert plant.truth()["line_on_tape"] == plant.truth()["comp_on_tape"] == [False, False, True]


def test_qtr_channels_discharge_in_proportion_to_the_pictures_darkness(tmp_path):
    picture(tmp_path / "floor.png", paint=[((60, 10, 70, 20), 64)])  # a dark grey, 0.749 dark
    qtr = {"kind": "qtr", "name": "q", "offsets_m": [[0.0, 0.0], [-0.1, 0.0], [-0.6, 0.0]], "emitter": "none"}
    plant = course(tmp_path, [qtr], world={"start_pose": [0.75, 0.35, 0.0]})  # white, dark grey, black
    times = []
    for i in range(3):
        t = 1000 + 20_000 * i
        plant.advance_to(t)
        plant.set_input(f"q.{i}", 1)
        plant.advance_to(t + 10)
        plant.set_input(f"q.{i}", RELEASED)
        plant.advance_to(t + 10_000)
    times = plant.truth()["q_discharge_us"]
    assert times == [150, round(150 + (1 - 64 / 255) * (800 - 150)), 800], times
    assert plant.truth()["q_on_tape"] == [False, True, True]


def test_the_bodys_tape_and_the_picture_together_read_the_darker(tmp_path):
    picture(tmp_path / "floor.png")
    line = {"kind": "line_sensor", "name": "line", "offsets_m": [[0.0, 0.0]]}
    plant = course(tmp_path, [line], tape=[[0.75, 0.0], [0.75, 0.5]], world={"start_pose": [0.75, 0.1, 0.0]})
    assert plant.output("line.0") == 58000, "the tape on the white of the picture"


@pytest.mark.parametrize(
    ("world", "message"),
    [
        ({"picture": None}, r"\[world\] picture: expected the floor's picture"),
        ({"mm_per_px": None}, r"\[world\] mm_per_px, width_m: expected the picture's scale"),
        ({"width_m": 1.0}, r"\[world\] mm_per_px, width_m: expected the picture's scale, one of them \(not both\)"),
        ({"picture": "no.png"}, r"\[world\] picture: cannot read /.*/no\.png \(No such file or directory\)"),
        ({"picture": "notes.txt"}, r"\[world\] picture: cannot read /.*/notes\.txt \(not a picture Pillow reads"),
        ({"start_pose": [1.5, 0.1, 0.0]}, r"\[world\] start_pose: \[1\.5, 0\.1, 0\.0\] is off the picture"),
        ({"mm_per_px": 0}, r"world_options mm_per_px: expected a number of millimetres from 0\.01"),
        ({"picture": 3}, r"world_options picture: expected a picture's path, relative to the rig file"),
    ],
)
def test_a_picture_missing_unreadable_or_without_its_scale_is_refused_by_name(tmp_path, world, message):
    picture(tmp_path / "floor.png")
    (tmp_path / "notes.txt").write_text("a course, in words\n")
    with pytest.raises(PartsError, match=message):
        course(tmp_path, world=world)


def test_a_changed_picture_is_read_again(tmp_path):
    picture(tmp_path / "floor.png")
    assert floor_of(tmp_path).darkness(0.9, 0.1) == 0.0
    picture(tmp_path / "floor.png", paint=[((80, 30, 100, 50), 0)])
    assert floor_of(tmp_path).darkness(0.9, 0.1) == 1.0


SVG = """<?xml version="1.0"?>
<svg xmlns="http://www.w3.org/2000/svg" width="500" height="250" viewBox="0 0 500 250">
  <rect x="0" y="0" width="250" height="125" fill="black"/>
  <path d="M 300 200 H 480" stroke="#000" stroke-width="10" fill="none"/>
</svg>
"""


def test_an_svg_drawing_is_drawn_at_a_millimetre_a_pixel_at_its_scale(tmp_path):
    """The same floor as the PNG's (a black quarter at the top-left) drawn as an SVG, 500 x
    250 units at 2 mm a unit (1 x 0.5 m): drawn at 1 mm a pixel, 1000 x 500 pixels; a 10-unit
    stroke is 20 mm of tape, its edges a pixel's ramp."""
    (tmp_path / "floor.svg").write_text(SVG)
    floor = floor_of(tmp_path, picture="floor.svg", mm_per_px=2.0)
    assert (floor.width, floor.height) == (1000, 500) and floor.size_m == (1.0, 0.5), (floor.width, floor.height)
    assert floor.darkness(0.1, 0.4) == 1.0 and floor.darkness(0.1, 0.1) == 0.0, "the top-left quarter is black"
    assert floor.darkness(0.7, 0.1) == 1.0, "on the stroke (y 0.09..0.11 m)"
    assert floor.darkness(0.7, 0.115) == 0.0 and floor.darkness(0.7, 0.085) == 0.0, "beside it: white"
    assert 0.3 < floor.darkness(0.7, 0.110) < 0.7, "its edge (at a pixel boundary): half way up the ramp"
    by_width = floor_of(tmp_path, picture="floor.svg", mm_per_px=None, width_m=2.0)
    assert (by_width.width, by_width.size_m) == (2000, (2.0, 1.0)), "width_m: the whole width, still 1 mm a pixel"


def test_an_svg_that_is_not_a_drawing_or_names_a_file_is_refused_by_name(tmp_path):
    (tmp_path / "bad.svg").write_text("<svg xmlns='http://www.w3.org/2000/svg' width='10' height='10'><rect")
    with pytest.raises(PartsError, match=r"\[world\] picture: cannot read /.*/bad\.svg \(not an SVG drawing CairoSVG"):
        course(tmp_path, world={"picture": "bad.svg"})
    secret = tmp_path / "secret.png"
    picture(secret)  # (all black where the drawing would paint it, if it could read it)
    (tmp_path / "peek.svg").write_text(
        "<svg xmlns='http://www.w3.org/2000/svg' xmlns:xlink='http://www.w3.org/1999/xlink' width='100' height='50'>"
        f"<image xlink:href='file://{secret}' width='100' height='50'/></svg>"
    )
    floor = floor_of(tmp_path, picture="peek.svg", mm_per_px=10.0)
    assert floor.darkness(0.1, 0.4) == 0.0, "expected the drawing's file reference not followed (white floor)"
