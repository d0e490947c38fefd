"""World ``line_course``: a line follower's course, the floor drawn as a picture.

The picture (a PNG, or any raster picture Pillow reads: JPEG, BMP, GIF, TIFF; or an SVG
drawing, drawn at a millimetre a pixel) is the floor seen from above, its top edge the far
side: the world's x runs to the right along its bottom edge, y up it, (0, 0) at its
bottom-left corner. Its scale is ``mm_per_px`` (an SVG's: millimetres a unit of the
drawing, a CSS px) or its whole width, ``width_m``. What the line sensors (``line_sensor``,
``qtr``) see under each sensor is the picture's darkness there (1 - its grey level / 255:
a colour is taken at its luminance, a transparent pixel as white), between the four
nearest pixel centres (``sample = "bilinear"``: an edge is a ramp a pixel wide) or the
nearest pixel's (``"nearest"``: a step). The file is read each time the plant is built,
and decoded once
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
        Opt(
            "picture",
            FileName("a picture's path, relative to the rig file"),
            None,
            "the floor's picture (a PNG, or an SVG drawing)",
        ),
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
            raise PartsError(
                "[world] picture: expected the floor's picture (a PNG or an SVG, relative to the rig file)"
            )
        if (o["mm_per_px"] is None) == (o["width_m"] is None):
            raise PartsError("[world] mm_per_px, width_m: expected the picture's scale, one of them (not both)")
        gray, width, height, m_per_px = read_floor(Path(o["picture"]), o["width_m"], o["mm_per_px"])
        floor = PictureFloor(gray, width, height, m_per_px, bilinear=o["sample"] == "bilinear")
        w_m, h_m = floor.size_m
        world = rectangle(w_m, h_m, name=f"line course {w_m:.3g} x {h_m:.3g} m")
        world.floor = floor
        start = o["start_pose"] or (w_m / 2, h_m / 2, 0.0)
        x, y, _ = start
        if not (0 <= x <= w_m and 0 <= y <= h_m):
            raise PartsError(f"[world] start_pose: {list(start)} is off the picture (0..{w_m:g} x 0..{h_m:g} m)")
        return world, tuple(float(v) for v in start)


def read_floor(path: Path, width_m: float | None, mm_per_px: float | None) -> tuple[bytes, int, int, float]:
    """The floor's picture at ``path`` at its scale (its whole width, or millimetres a
    pixel): grey levels, width, height and metres a pixel. A raster picture is taken pixel
    for pixel; an SVG drawing is drawn at :data:`SVG_MM_PER_PX` (its scale: its width, or
    millimetres a unit of the drawing, a CSS px)."""
    data = _read(path)
    if not _is_svg(data):
        gray, width, height = _decoded(data, str(path))
        return gray, width, height, (width_m / width if width_m is not None else mm_per_px / 1000)
    natural = _svg_png(data, str(path), 1.0)
    with Image.open(io.BytesIO(natural)) as first:
        units_w, units_h = first.size  # the drawing's size in its own units (CSS px)
    floor_m = width_m if width_m is not None else units_w * mm_per_px / 1000
    scale = floor_m * 1000 / SVG_MM_PER_PX / units_w
    if units_w * scale * units_h * scale > MAX_PIXELS:
        raise PartsError(
            f"[world] picture: {path} drawn at {SVG_MM_PER_PX:g} mm a pixel is more than {MAX_PIXELS:,} pixels"
        )
    gray, width, height = _decoded(_svg_png(data, str(path), scale), str(path))
    return gray, width, height, floor_m / width


SVG_MM_PER_PX = 1.0
"""An SVG floor is drawn at a millimetre a pixel (its edges anti-aliased by cairo), then read
as a picture."""


def _is_svg(data: bytes) -> bool:
    head = data[:1024].lstrip(b"\xef\xbb\xbf \t\r\n").lower()
    return (
        head.startswith(b"<svg") or (head.startswith(b"<?xml") and b"<svg" in head) or head.startswith(b"<!doctype svg")
    )


@functools.lru_cache(maxsize=4)
def _svg_png(data: bytes, path: str, scale: float) -> bytes:
    """The drawing drawn on white at ``scale`` by CairoSVG (which reads no file or URL the
    drawing names: its ``unsafe`` off), as a PNG."""
    try:
        import cairosvg
    except OSError as e:  # (cairocffi finds no libcairo)
        raise PartsError(
            f"[world] picture: {path} is an SVG, which needs the cairo library ({e}); or export it as a PNG"
        ) from None
    try:
        return cairosvg.svg2png(bytestring=data, scale=scale, background_color="white")
    except Exception as e:  # noqa: BLE001  (the XML parser's, cairo's: named, not a traceback)
        raise PartsError(f"[world] picture: cannot read {path} (not an SVG drawing CairoSVG reads: {e})") from None


def _read(path: Path) -> bytes:
    """The picture file's bytes (read each time the plant is built, decoded once per
    content); a PartsError names the file and why it cannot be read."""
    try:
        return path.read_bytes()
    except OSError as e:
        raise PartsError(f"[world] picture: cannot read {path} ({e.strerror or e})") from None


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
