"""The pictures a plant's displays showed, as files of the trace folder
(``docs/traces.md``): for each part that keeps its frames (``display_frames()``: an
``ssd1306``, an ``sh1106``, an ``ht16k33``, an ``st7789`` in colour), ``<name>.png``, the
last picture, ``<name>.gif``, every distinct picture in turn, each held for the virtual
time it was shown (at least 20 ms, a GIF's least), and ``<name>.frames.png``, a film strip
of up to ``FILM`` of them side by side (of those held for 20 ms or more: all when there
are no more, else spread evenly from the first to the last), each ``STRIP_SCALE`` times
larger with the virtual time it was first shown written under it, which the header's
``displays`` lists (:func:`describe_displays`). Pixels are drawn ``SCALE`` times larger (a panel wider than 128
pixels less: :func:`scale_for`), a monochrome panel's lit ones in its colour on black, a
colour panel's in theirs.

And the floor the robot drove on, when its world has one drawn (``line_course``):
``floor.png``, its picture's grey levels as the line sensors saw them, which the
trajectory plot lays under the path (the header's ``world`` says where: ``floor``)."""

from PIL import Image, ImageDraw

SCALE = 4
LIT = (120, 220, 255)  # a white-blue OLED's glow
DARK = (0, 0, 0)
LEAST_MS = 20
LAST_HOLD_MS = 1000
FILM = 6  # pictures in a display's film strip at most
STRIP_SCALE = 2
GAP_PX = 6  # between two pictures of the strip
LABEL_PX = 14  # the band under each picture with its time
STRIP = "{name}.frames.png"


def displays(plant) -> list:
    """(name, width, height, [(t_us, picture)]) of each part with a display (the plant's ``displays()``)."""
    return plant.displays()


def image(width: int, height: int, picture: bytes, scale: int = SCALE) -> Image.Image:
    """A picture as an RGB image, scaled: a byte a pixel (rows of ``width``; 0: dark, else
    lit in ``LIT``), or two, a colour panel's (RGB565 big-endian, as an ``st7789`` keeps it;
    each field scaled to 0-255)."""
    if len(picture) == 2 * width * height:
        rgb = _rgb565(width, height, picture)
    else:
        mono = Image.frombytes("L", (width, height), bytes(255 if p else 0 for p in picture))
        lit = [mono.point(lambda v, c=c, d=d: c if v else d) for c, d in zip(LIT, DARK, strict=True)]
        rgb = Image.merge("RGB", lit)
    return rgb.resize((width * scale, height * scale), Image.NEAREST)


def scale_for(width: int) -> int:
    """The scale a display's pictures are drawn at: ``SCALE`` for a 128-pixel OLED, less
    for a wider panel (a 240-pixel TFT's at 2), so that none is wider than 512 pixels."""
    return max(1, min(SCALE, 512 // width))


def _rgb565(width: int, height: int, picture: bytes) -> Image.Image:
    little = bytearray(len(picture))  # (Pillow's "BGR;16" is RGB565 little-endian)
    little[0::2], little[1::2] = picture[1::2], picture[0::2]
    return Image.frombytes("RGB", (width, height), bytes(little), "raw", "BGR;16")


def film(frames: list) -> list:
    """The pictures of a display's film strip: of those shown for ``LEAST_MS`` or longer
    (and the last), not the passing ones a show drawn page by page makes on its way, all
    when there are ``FILM`` or fewer, else ``FILM`` spread evenly from the first to the last."""
    ends = [t for t, _ in frames[1:]] + [None]
    held = [f for f, end in zip(frames, ends, strict=True) if end is None or end - f[0] >= LEAST_MS * 1000]
    n = len(held)
    if n <= FILM:
        return held
    return [held[round(i * (n - 1) / (FILM - 1))] for i in range(FILM)]


def describe_displays(plant) -> dict:
    """For the header: each display's ``{"frames": how many distinct pictures it kept,
    "strip": its film strip's file, "strip_t_us": when each of the strip's pictures was
    first shown}``, by the part's name."""
    return {
        name: {"frames": len(frames), "strip": STRIP.format(name=name), "strip_t_us": [t for t, _ in film(frames)]}
        for name, _w, _h, frames in displays(plant)
        if frames
    }


FLOOR = "floor.png"


def floor_of(plant):
    """The plant's world's floor picture (a ``sim_plant.floor.PictureFloor``), or None."""
    world = plant.world
    return world.floor if world is not None else None


def describe_floor(plant) -> dict | None:
    """Where the floor's picture lies, for the header's ``world``: ``{"picture": "floor.png",
    "extent_m": [x0, x1, y0, y1]}``; None without one."""
    floor = floor_of(plant)
    if floor is None:
        return None
    w_m, h_m = floor.size_m
    return {"picture": FLOOR, "extent_m": [0.0, w_m, 0.0, h_m]}


def writers(plant) -> list:
    """(file name, write(path)) for each display's two files, and the floor's picture."""
    floor = floor_of(plant)
    out = [(FLOOR, lambda path: _floor_png(path, floor))] if floor is not None else []
    for name, width, height, frames in displays(plant):
        blank = bytes(width * height)
        shown = frames or [(0, blank)]
        out.append((f"{name}.png", lambda path, w=width, h=height, s=shown: _png(path, w, h, s)))
        out.append((f"{name}.gif", lambda path, w=width, h=height, s=shown: _gif(path, w, h, s)))
        if frames:
            picked = film(frames)
            out.append((STRIP.format(name=name), lambda path, w=width, h=height, s=picked: _strip(path, w, h, s)))
    return out


def _floor_png(path, floor) -> None:
    Image.frombytes("L", (floor.width, floor.height), floor.gray).save(path, format="PNG")


def _png(path, width, height, frames) -> None:
    image(width, height, frames[-1][1], scale_for(width)).save(path, format="PNG")


def _gif(path, width, height, frames) -> None:
    times = [t for t, _ in frames]
    durations = [max(LEAST_MS, (b - a) // 1000) for a, b in zip(times, times[1:])] + [LAST_HOLD_MS]
    images = [image(width, height, picture, scale_for(width)) for _t, picture in frames]
    images[0].save(path, format="GIF", save_all=True, append_images=images[1:], duration=durations, loop=0)


def _strip(path, width, height, frames) -> None:
    tile_w, tile_h = width * STRIP_SCALE, height * STRIP_SCALE
    strip = Image.new("RGB", (len(frames) * (tile_w + GAP_PX) - GAP_PX, tile_h + LABEL_PX), (255, 255, 255))
    draw = ImageDraw.Draw(strip)
    for i, (t_us, picture) in enumerate(frames):
        x = i * (tile_w + GAP_PX)
        strip.paste(image(width, height, picture, STRIP_SCALE), (x, 0))
        draw.text((x + 2, tile_h + 2), f"{t_us / 1e6:.3f} s", fill=(40, 40, 40))
    strip.save(path, format="PNG")
