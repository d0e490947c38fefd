"""Writing only where a command was told to, and never over what it reads.

Every command that writes (run, replay, plot, diff, shrink, campaign, scenario, init,
import-wokwi, setup) makes its folders and files through this module:

- :func:`output_folder`: the folder a command writes into, refused when it is one of
  the command's inputs, holds one, or lies inside one (but for the sub-folder the command
  owns there, e.g. a trace folder's ``plots/``);
- :func:`make_folder`: a folder made (or taken) below a folder already trusted, each part
  of the way a real folder: a link there, dangling or not, is refused by name and target;
- :func:`fresh_file`, :func:`open_write`, :func:`replacing`, :func:`write_text`: a file
  created or replaced in a real folder without following a link at its name (``O_NOFOLLOW``,
  ``O_EXCL``, a temporary file renamed over the name, which replaces a link itself);
- :func:`regular_file` and :func:`kind`: what a reader of a user's folder may open (a FIFO,
  a socket or a device is named and skipped, never opened: opening a FIFO waits for ever).

A refusal is an :class:`~host.core.errors.OutputRefused` (a ConfigError: exit code 2 from
the command line) naming the path, the link's target or the input it would overwrite.
``docs/security.md`` (nothing written outside the folder named) states the guarantee."""

import errno
import os
import secrets
import stat
from contextlib import contextmanager
from pathlib import Path

from host.core.errors import OutputRefused

_NOFOLLOW = getattr(os, "O_NOFOLLOW", 0)
_CLOEXEC = getattr(os, "O_CLOEXEC", 0)


def link_text(path) -> str:
    """``path is a link to TARGET`` (the target as the link holds it)."""
    try:
        target = os.readlink(path)
    except OSError:
        target = "?"
    return f"{path} is a link to {target}"


def kind(path, follow: bool = False) -> str | None:
    """What ``path`` is when it is not a regular file or a folder (``"a FIFO"``, ``"a
    socket"``, ``"a device"``, ``"a link"``), following a link only with ``follow``; None
    for a file, a folder or nothing."""
    try:
        mode = (os.stat if follow else os.lstat)(path).st_mode
    except OSError:
        return None
    if stat.S_ISREG(mode) or stat.S_ISDIR(mode):
        return None
    if stat.S_ISLNK(mode):
        return "a link"
    if stat.S_ISFIFO(mode):
        return "a FIFO"
    if stat.S_ISSOCK(mode):
        return "a socket"
    return "a device"


def regular_file(path) -> bool:
    """``path`` (its link followed, as a reader opens it) is a regular file: never a FIFO,
    a socket or a device, which a read would wait on or never end."""
    try:
        return stat.S_ISREG(os.stat(path).st_mode)
    except (OSError, ValueError):
        return False


def refuse_link(path, what: str = "") -> None:
    """An OutputRefused when ``path`` itself is a symbolic link (dangling or not)."""
    path = Path(path)
    if path.is_symlink():
        raise OutputRefused(
            f"{what + ' ' if what else ''}{link_text(path)}: the harness writes no file or folder through "
            "a link (expected a real file or folder there, or nothing: remove the link, or name its target)"
        )


def _relation(out: Path, other: Path) -> str | None:
    if out == other:
        return "is"
    if other.is_relative_to(out):
        return "holds"
    if out.is_relative_to(other):
        return "inside"
    return None


def output_folder(
    folder,
    *,
    what: str = "--out",
    inputs: dict | None = None,
    owned: dict | None = None,
    base=None,
    create: bool = True,
) -> Path:
    """The folder a command writes into, made, as a real path (no link in it).

    ``inputs`` (a label, e.g. ``"the trace folder TRACE"``, to each folder or file the
    command reads) are compared with it, links resolved: an output that is an input, holds
    one, or lies inside one is refused, unless it lies in the sub-folder ``owned[label]``
    of that input (a trace folder's ``plots/``, ``replay/``, ``diff/``: the command's own
    default; an absolute path is taken as it is). ``base``: the folder the user named,
    whose links are followed (default: the output's parent); the output and every folder
    made between the two must be real folders, never links. ``create=False``: checked
    only, made later (by :func:`make_folder`), so a command refused afterwards leaves none."""
    folder = Path(folder)
    real = Path(os.path.realpath(folder))
    for label, path in (inputs or {}).items():
        other = Path(os.path.realpath(path))
        relation = _relation(real, other)
        sub = (owned or {}).get(label)
        if relation == "inside" and sub and real.is_relative_to(os.path.realpath(other / sub)):
            continue
        if relation == "is":
            raise OutputRefused(
                f"{what} {folder}: is {label} ({path}) that the command reads: writing there would "
                "overwrite it; expected another folder"
            )
        if relation == "holds":
            raise OutputRefused(
                f"{what} {folder}: holds {label} ({path}) that the command reads; expected a folder outside it"
            )
        if relation == "inside":
            where = f", or {Path(path) / sub} (the default)" if sub else ""
            raise OutputRefused(
                f"{what} {folder}: lies inside {label} ({path}) that the command reads; expected a "
                f"folder outside it{where}"
            )
    return make_folder(folder, base=base, what=what, create=create)


def make_folder(path, base=None, what: str = "", create: bool = True) -> Path:
    """``path`` made where it is missing, as a real path. ``base`` (default: ``path``'s
    parent) is trusted as named (its links followed, made if missing); each part of
    ``path`` below it must be a real folder or nothing: a link (dangling too) or a file
    there is refused by name. Returns the folder's real path. ``create=False``: the
    parts that are there checked, nothing made."""
    path = Path(path)
    base = Path(base) if base is not None else path.parent
    try:
        rel = path.relative_to(base)
    except ValueError:
        raise ValueError(f"{path} is not below {base}") from None
    try:
        if create:
            base.mkdir(parents=True, exist_ok=True)
    except FileExistsError:
        raise OutputRefused(f"{what + ' ' if what else ''}{base}: exists and is not a folder") from None
    current = Path(os.path.realpath(base))
    missing = not current.is_dir()
    shown = base
    for part in rel.parts:
        if part in ("", "."):
            continue
        if part == "..":
            raise OutputRefused(f"{what + ' ' if what else ''}{path}: '..' in a folder the harness makes")
        current, shown = current / part, shown / part
        if missing:
            continue
        try:
            if create:
                os.mkdir(current)
                continue
            os.lstat(current)
        except FileExistsError:
            pass
        except FileNotFoundError:
            missing = True
            continue
        mode = os.lstat(current).st_mode
        if stat.S_ISLNK(mode):
            refuse_link(shown, what)
        if not stat.S_ISDIR(mode):
            raise OutputRefused(
                f"{what + ' ' if what else ''}{shown}: is {kind(current) or 'a file'}, expected a folder "
                "(or nothing there)"
            )
    return current


def drop_links(folder) -> Path:
    """Every link inside ``folder`` (at any depth) removed, never followed: before a
    library that opens its own files by name (coverage.py's data and HTML) writes there."""
    folder = Path(folder)
    for top, dirs, files in os.walk(folder):  # (os.walk enters no linked folder)
        for name in [*dirs, *files]:
            path = Path(top, name)
            if path.is_symlink():
                path.unlink()
    return folder


def fresh_file(path) -> Path:
    """An empty file made at ``path`` whatever was there (an earlier file, a link, left by a
    run that was killed: removed, never followed), created exclusively so that a link put
    there is never written through."""
    path = Path(path)
    if path.is_symlink():
        path.unlink()
    flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | _NOFOLLOW | _CLOEXEC
    try:
        fd = os.open(path, flags, 0o666)
    except FileExistsError:
        path.unlink()
        fd = os.open(path, flags, 0o666)
    os.close(fd)
    return path


def open_write(path, mode: str = "w", **kwargs):
    """``open(path, mode)`` for writing a new or existing regular file, never through a link
    at its name (refused by name and target)."""
    path = Path(path)
    refuse_link(path)
    flags = os.O_WRONLY | os.O_CREAT | _NOFOLLOW | _CLOEXEC
    flags |= os.O_APPEND if mode.startswith("a") else os.O_TRUNC
    try:
        fd = os.open(path, flags, 0o666)
    except OSError as e:
        if path.is_symlink():  # (put there since the check)
            refuse_link(path)
        raise e
    try:
        return open(fd, mode, **kwargs)  # noqa: SIM115  (the caller closes it)
    except BaseException:
        os.close(fd)
        raise


def write_new(path, text: str) -> Path:
    """``text`` into a new file ``path`` (UTF-8), made exclusively: anything already at the
    name, a link most of all, is refused by name (FileExistsError for a file)."""
    path = Path(path)
    refuse_link(path)
    fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL | _NOFOLLOW | _CLOEXEC, 0o666)
    with open(fd, "w", encoding="utf-8") as f:
        f.write(text)
    return path


@contextmanager
def replacing(path, refuse_links: bool = False):
    """Yields a temporary path in ``path``'s folder (made exclusively, a hidden name) to
    write; renamed over ``path`` when the block ends without error (a link at ``path`` is
    replaced, its target untouched), removed otherwise. ``refuse_links``: a link at
    ``path`` is refused rather than replaced."""
    path = Path(path)
    if refuse_links:
        refuse_link(path)
    flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | _NOFOLLOW | _CLOEXEC
    for _ in range(100):
        temp = path.with_name(f".{path.name}.{secrets.token_hex(4)}.part")
        try:
            os.close(os.open(temp, flags, 0o666))  # (the umask's mode, as open() gives a new file)
            break
        except FileExistsError:
            continue
    else:
        raise FileExistsError(errno.EEXIST, "no free temporary name", str(path))
    try:
        yield Path(temp)
        os.replace(temp, path)
    except BaseException:
        Path(temp).unlink(missing_ok=True)
        raise


def write_text(path, text: str, refuse_links: bool = False) -> Path:
    """``text`` into ``path`` whole (UTF-8), by :func:`replacing`."""
    with replacing(path, refuse_links) as temp:
        temp.write_text(text, encoding="utf-8")
    return Path(path)
