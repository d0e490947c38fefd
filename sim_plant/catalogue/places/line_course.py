"""World ``line_course``: a line follower's course, the floor drawn as a picture.

The picture (a PNG, or any raster picture Pillow reads: JPEG, BMP, GIF, TIFF) is the
floor seen from above, its top edge the far side: the world's x runs to the right along
its bottom edge, y up it, (0, 0) at its bottom-left corner. Its scale is ``mm_per_px`` or
its whole width, ``width_m``. What the line sensors (``line_sensor``, ``qtr``) see under
each sensor is the picture's darkness there (1 - its grey level / 255: a colour is taken
at its luminance, a transparent pixel as white), between the four nearest pixel centres
(``sample = "bilinear"``: an edge is a ramp a pixel wide) or the nearest pixel's
(``"nearest"``: a step). The file is read each time the plant is built, and decoded once
per content. Walls stand along the picture's edges: the floor ends there."""

import functools
import io
from pathlib import Path

from PIL import Image, UnidentifiedImageError

from sim_plant.catalogue.base import Opt, PartsError, WorldType
from sim_plant.floor import PictureFloor
from sim_plant.option_table import POSE, FileName, Num, OneOf, length
from sim_plant.world import rectangle

MAX_PIXELS = 16_000_000  # 4000 x 4000: 4 m at a millimetre a pixel
WHITE = (255, 255, 255)


class LineCourse(WorldType):
    kind = "line_course"
    doc = (
        "A line follower's course: the floor drawn as a picture (a PNG), its scale mm_per_px or width_m, (0, 0) at"
        " its bottom-left corner, x along its bottom edge, y up it; line sensors (line_sensor, qtr) see its"
        " darkness (1 - grey/255; transparent is white), bilinear between pixel centres or the nearest pixel's;"
        " walls stand along its edges (docs/rig-file.md, 'A floor drawn as a picture')."
    )
    OPTIONS = (
        Opt("picture", FileName("a picture's path, relative to the rig file"), None, "the floor's picture (a PNG)"),
        Opt(
            "mm_per_px", Num("millimetres", 0.01, 1000, none=True), None, "millimetres a pixel: its scale (or width_m)"
        ),
        Opt("width_m", length(0.01, 100, none=True), None, "its whole width (or mm_per_px): the scale from it"),
        Opt(
            "start_pose",
            POSE,
            None,
            "where the robot starts, from the picture's bottom-left corner; its centre, heading along x, by default",
        ),
        Opt(
            "sample",
            OneOf(("bilinear", "nearest")),
            "bilinear",
            "the darkness between the four nearest pixels' centres, or the nearest pixel's",
        ),
    )

    def build(self):
        o = self.options
        if o["picture"] is None:
            raise PartsError("[world] picture: expected the floor's picture (a PNG, relative to the rig file)")
        if (o["mm_per_px"] is None) == (o["width_m"] is None):
            raise PartsError("[world] mm_per_px, width_m: expected the picture's scale, one of them (not both)")
        gray, width, height = read_picture(Path(o["picture"]))
        m_per_px = o["width_m"] / width if o["width_m"] is not None else o["mm_per_px"] / 1000
        floor = PictureFloor(gray, width, height, m_per_px, bilinear=o["sample"] == "bilinear")
        w_m, h_m = floor.size_m
        world = rectangle(w_m, h_m, name=f"line course {w_m:.3g} x {h_m:.3g} m")
        world.floor = floor
        start = o["start_pose"] or (w_m / 2, h_m / 2, 0.0)
        x, y, _ = start
        if not (0 <= x <= w_m and 0 <= y <= h_m):
            raise PartsError(f"[world] start_pose: {list(start)} is off the picture (0..{w_m:g} x 0..{h_m:g} m)")
        return world, tuple(float(v) for v in start)


def read_picture(path: Path) -> tuple[bytes, int, int]:
    """The picture at ``path`` as grey levels (a byte a pixel, rows from the top), its
    width and height; a PartsError names the file and why it cannot be read. The file is
    read each time, decoded once per content."""
    try:
        data = path.read_bytes()
    except OSError as e:
        raise PartsError(f"[world] picture: cannot read {path} ({e.strerror or e})") from None
    return _decoded(data, str(path))


@functools.lru_cache(maxsize=4)
def _decoded(data: bytes, path: str) -> tuple[bytes, int, int]:
    try:
        with Image.open(io.BytesIO(data)) as picture:
            width, height = picture.size
            if width * height > MAX_PIXELS:
                raise PartsError(
                    f"[world] picture: {path} is {width} x {height} pixels, more than {MAX_PIXELS:,}: scale it down"
                )
            picture.load()
            gray = _on_white(picture).convert("L")
    except UnidentifiedImageError:
        raise PartsError(
            f"[world] picture: cannot read {path} (not a picture Pillow reads: expected a PNG, JPEG, BMP or GIF)"
        ) from None
    except (OSError, ValueError, Image.DecompressionBombError) as e:
        raise PartsError(f"[world] picture: cannot read {path} ({e})") from None
    return gray.tobytes(), width, height


def _on_white(picture: Image.Image) -> Image.Image:
    """A picture with transparency laid on white paper (a transparent pixel is the floor's white)."""
    if picture.mode in ("RGBA", "LA", "PA") or "transparency" in picture.info:
        rgba = picture.convert("RGBA")
        paper = Image.new("RGBA", rgba.size, (*WHITE, 255))
        return Image.alpha_composite(paper, rgba)
    return picture
