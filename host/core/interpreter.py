"""The MicroPython interpreter the harness runs: MicroPython's unix port built from
Debian's ``micropython`` source package, or ``$MICROPYTHON``.

``python3 -m host.core.interpreter build`` fetches the pinned source with ``apt-get source``
through a project-local apt configuration (one ``deb-src`` line for the pinned suite, on the
Debian mirror this machine's apt already uses, :mod:`host.core.aptsources`; the sources
file, lists, cache and state under ``build/micropython/apt``), builds the standard variant with
``asyncio`` frozen in, and installs the binary at :func:`default_path`. It rebuilds
nothing when that binary exists. Standard library only: it runs before the venv.

Where the build goes (:func:`build_root`): in a checkout of the repository, its own
``build/micropython`` (``make setup``); installed as a package, the per-user cache
(``$XDG_CACHE_HOME/mpy-fil/micropython/<version>/``, ``~/.cache`` when unset), shared by
every project and virtual environment of that user, never inside ``site-packages``.
``mpy-fil setup`` (:func:`setup`) takes ``$MICROPYTHON``, else one already built, else a
``micropython`` on ``PATH`` of the pinned version, else builds it.

Before make, the patches in ``host/core/micropython/*.patch`` are applied to the unpacked
source (:func:`patch_tree`): ``hilcount.patch`` makes the VM count what the firmware executes
(bytecodes by opcode, calls into C, allocations, collections) and keep a stack of the running
bytecode functions, for MCU time (docs/mcu-time.md). The patches, the make options and the
frozen manifest make a build's identity (:func:`identity`), written beside each binary of a
checkout's build: a binary of another identity is rebuilt (:func:`current`).

A second variant, ``settrace`` (:func:`build_variant`): the same build with line tracing
(``sys.settrace``) for firmware coverage (docs/coverage.md), built only when coverage is
asked for, into its own objects (``build-settrace``) and binary (``micropython-settrace``
beside the standard one); ``$MICROPYTHON_SETTRACE`` overrides it. The standard build's
command and binary are untouched by it.
"""

import fcntl
import hashlib
import os
import shutil
import subprocess
import sys
from pathlib import Path

from host.core import aptsources, paths, safefs
from host.core.errors import SetupError

DEBIAN_VERSION = "1.25.0+ds-1"
"""Pinned source package version (Debian 13 "trixie" carries 1.25.0)."""
DEBIAN_SUITE = "trixie"
DEBIAN_KEYRING = "/usr/share/keyrings/debian-archive-keyring.gpg"

SETUP_HINT = "run `make setup`" if paths.CHECKOUT else "run `mpy-fil setup`"
"""What to do when there is no interpreter: the one command, as it runs where the harness is
(in a clone, ``mpy-fil`` is in ``.venv/bin`` and ``make setup`` builds into its build/)."""
HERE = Path(__file__).resolve().parent / "micropython"
APT_PACKAGES = ("gcc", "make", "pkg-config", "dpkg-dev", "xz-utils", "patch", "python3")
# The standard variant, less what needs libraries Debian strips from the source (+ds):
# TLS (mbedTLS/axTLS) and btree (Berkeley DB); and less ffi, which no board has (a firmware
# could call the host's libc through it: docs/security.md).
# With the shim's hot path in C (host/shim/cmod/_hilfast), linked in as a user C module: the
# shim uses it when it can import it, its pure-Python path otherwise (a user's own interpreter).
# (The folder is named from the project's root here, as the manifest records it; given to make
# as an absolute path: :func:`_absolute`.)
MAKE_OPTIONS = (
    "VARIANT=standard",
    "MICROPY_PY_SSL=0",
    "MICROPY_PY_BTREE=0",
    "MICROPY_PY_FFI=0",
    "USER_C_MODULES=host/shim/cmod",
)
VARIANT_OPTIONS = {
    "standard": (),
    # line tracing (py/profile.c; it implies MICROPY_PERSISTENT_CODE_SAVE), objects of its own
    "settrace": ("CFLAGS_EXTRA=-DMICROPY_PY_SYS_SETTRACE=1", "BUILD=build-settrace"),
}
"""What each variant adds to :data:`MAKE_OPTIONS` (its make command: :func:`make_options`)."""
PROJECT_ROOT = HERE.parent.parent.parent
"""What a relative folder in :data:`MAKE_OPTIONS` is relative to."""


PATCHES = tuple(sorted(HERE.glob("*.patch")))
"""Applied in order to the unpacked source before make (``patch -p1``)."""
APPLIED = ".mpy-fil-applied.patch"
"""In the source tree: the patches' text as last applied (:func:`patch_tree`)."""


def patches_text() -> str:
    return "".join(p.read_text() for p in PATCHES)


def identity(variant: str = "standard") -> str:
    """What a build is made of: a hash of its make options, the patches, the frozen manifest
    and the user C modules' files. Written beside the binary (``<binary>.identity``)."""
    h = hashlib.sha256()
    h.update(DEBIAN_VERSION.encode() + b"\0" + "\0".join(make_options(variant)).encode() + b"\0")
    h.update(patches_text().encode())
    h.update((HERE / "manifest.py").read_bytes())
    cmod = PROJECT_ROOT / "host" / "shim" / "cmod"
    for f in sorted(cmod.rglob("*")):
        if f.is_file():
            h.update(str(f.relative_to(cmod)).encode() + b"\0" + f.read_bytes())
    return h.hexdigest()[:16]


def _identity_file(target: Path) -> Path:
    return target.with_name(target.name + ".identity")


def _in_checkout(target: Path) -> bool:
    return paths.CHECKOUT and Path(target).is_relative_to(build_root(checkout=True))


def current(target: Path, variant: str) -> bool:
    """The binary at ``target`` is there and, in a checkout's build/ (where the patches and
    the C modules change under it), of this build's identity. (The per-user cache of an
    installed release holds that release's build: docs/ci.md caches its binary alone,
    keyed on the release.)"""
    if not target.is_file():
        return False
    if not _in_checkout(target):
        return True
    marker = _identity_file(target)
    return marker.is_file() and marker.read_text().strip() == identity(variant)


def patch_tree(tree: Path) -> None:
    """Apply :data:`PATCHES` to the source tree, once: a tree patched with other text is
    first unpatched (``patch -R`` with the text recorded in :data:`APPLIED`)."""
    want = patches_text()
    applied = tree / APPLIED
    have = applied.read_text() if applied.is_file() else ""
    if have == want:
        return
    if have:
        _log("unpatching the source (the patches changed)")
        _patch(tree, have, "-R")
        applied.unlink()
    if want:
        _log("patching the source: " + ", ".join(p.name for p in PATCHES))
        _patch(tree, want, "--dry-run")
        _patch(tree, want)
        safefs.write_text(applied, want)


def _patch(tree: Path, text: str, *flags: str) -> None:
    out = subprocess.run(
        ["patch", "-p1", "--batch", "--no-backup-if-mismatch", *flags],
        input=text,
        text=True,
        cwd=tree,
        capture_output=True,
    )
    if out.returncode != 0:
        raise SetupError(f"patch {' '.join(flags)} failed in {tree}:\n{out.stdout}{out.stderr}")


def _absolute(option: str) -> str:
    """``USER_C_MODULES=host/shim/cmod`` as make needs it (an absolute folder)."""
    name, _, value = option.partition("=")
    return f"{name}={PROJECT_ROOT / value}" if name == "USER_C_MODULES" else option


def build_root(checkout: bool | None = None) -> Path:
    """The folder builds go to: a checkout's ``build/micropython``, else the per-user cache's
    ``micropython`` (:func:`host.core.paths.user_cache`)."""
    checkout = paths.CHECKOUT if checkout is None else checkout
    return paths.BUILD / "micropython" if checkout else paths.user_cache() / "micropython"


def made_root(root: Path) -> Path:
    """The build folder ``root``, made: below the per-user cache's parent (``~/.cache``) or
    the repository, each folder on the way a real one (a link there is refused by name,
    never built through)."""
    root = Path(root)
    for base in (paths.user_cache().parent, paths.REPO):
        if root.is_relative_to(base):
            return safefs.make_folder(root, base=base)
    return safefs.make_folder(root)


def default_path(root: Path | None = None) -> Path:
    """The built binary: ``<root>/<Debian version>/micropython``."""
    return (root or build_root()) / DEBIAN_VERSION / "micropython"


def variant_path(variant: str, root: Path | None = None) -> Path:
    """A variant's binary: the standard one at :func:`default_path`, another beside it
    (``micropython-<variant>``)."""
    if variant not in VARIANT_OPTIONS:
        raise SetupError(f"no interpreter variant {variant!r}: expected one of {', '.join(VARIANT_OPTIONS)}")
    target = default_path(root)
    return target if variant == "standard" else target.with_name(f"micropython-{variant}")


def make_options(variant: str = "standard") -> tuple[str, ...]:
    """The unix port's make options of a variant (without the frozen manifest)."""
    return (*MAKE_OPTIONS, *VARIANT_OPTIONS[variant])


def _executable(path: Path) -> bool:
    return path.is_file() and os.access(path, os.X_OK)


def on_path() -> Path | None:
    """A ``micropython`` on ``PATH`` of the pinned version (major.minor), or None."""
    found = shutil.which("micropython")
    if found is None:
        return None
    return Path(found) if version_problem(Path(found)) is None else None


def version_problem(path: Path) -> str | None:
    """Why the interpreter at ``path`` will not do (not the pinned MicroPython version),
    or None when it will."""
    want = DEBIAN_VERSION.split("+")[0].rsplit(".", 1)[0]  # "1.25"
    try:
        line = version(path)
    except (OSError, subprocess.SubprocessError) as e:
        return f"{path} does not run as MicroPython ({e})"
    if not line.startswith(f"MicroPython v{want}."):
        return f"{path} is {line or 'of no known version'}; the harness needs MicroPython {want}"
    return None


def find() -> Path:
    """The interpreter to run: ``$MICROPYTHON`` if set, else the one built by setup, else
    one on ``PATH`` of the pinned version. A :class:`SetupError` that says the one
    command to run when there is none."""
    override = os.environ.get("MICROPYTHON")
    if override:
        if not _executable(Path(override)):
            raise SetupError(f"MICROPYTHON={override} is not an executable file")
        return Path(override)
    for path in dict.fromkeys((default_path(), default_path(build_root(checkout=False)))):
        if _executable(path):
            return path
    found = on_path()
    if found is not None:
        return found
    raise SetupError(f"no MicroPython interpreter (looked at $MICROPYTHON, {default_path()}, PATH): {SETUP_HINT}")


def version(path: Path | None = None) -> str:
    """The interpreter's own version line, e.g. 'MicroPython v1.25.0+ds-1 on ...'."""
    path = path or find()
    out = subprocess.run(
        [str(path), "-c", "import sys; print(sys.version.split('; ')[-1])"],
        capture_output=True,
        text=True,
        timeout=10,
        check=True,
    )
    return out.stdout.strip()


def _log(msg: str) -> None:
    print(f"[micropython] {msg}", flush=True)


def _missing_tools() -> list[str]:
    missing = []
    for tool, package in (
        ("gcc", "gcc"),
        ("make", "make"),
        ("pkg-config", "pkg-config"),
        ("dpkg-source", "dpkg-dev"),
        ("xz", "xz-utils"),
        ("patch", "patch"),
        ("apt-get", "apt"),
    ):
        if shutil.which(tool) is None:
            missing.append(package)
    if shutil.which("pkg-config") and subprocess.run(["pkg-config", "--exists", "libffi"]).returncode != 0:
        missing.append("libffi-dev")
    return missing


def ensure_tools() -> None:
    missing = _missing_tools()
    if not missing:
        return
    if "apt" in missing or os.geteuid() != 0:
        raise SetupError(
            "building MicroPython needs these Debian packages: "
            + " ".join(missing)
            + "\n  install them with: sudo apt-get install -y "
            + " ".join(p for p in missing if p != "apt")
        )
    _log("installing build packages: " + " ".join(missing))
    subprocess.run(["apt-get", "update", "-qq"], check=True)
    subprocess.run(
        ["apt-get", "install", "-y", "-qq", "--no-install-recommends", *missing],
        check=True,
        env={**os.environ, "DEBIAN_FRONTEND": "noninteractive"},
    )
    still = _missing_tools()
    if still:
        raise SetupError("still missing after apt-get install: " + " ".join(still))


def _apt(root: Path, *args: str) -> list[str]:
    apt = root / "apt"
    opts = {
        "Dir::Etc::SourceList": apt / "sources.list",
        "Dir::Etc::SourceParts": apt / "sources.list.d",
        "Dir::Etc::PreferencesParts": apt / "preferences.d",
        "Dir::State": apt / "state",
        "Dir::State::Lists": apt / "lists",
        "Dir::State::status": apt / "status",
        "Dir::Cache": apt / "cache",
        "Debug::NoLocking": "1",
        "APT::Sandbox::User": "root" if os.geteuid() == 0 else os.environ.get("USER", "nobody"),
    }
    flags = [f"-o{k}={v}" for k, v in opts.items()]
    return ["apt-get", "-q", *flags, *args]


def _tree(root: Path) -> Path:
    return root / "src" / f"micropython-{DEBIAN_VERSION.rsplit('-', 1)[0]}"


def source_tree() -> Path:
    """MicroPython's source as the build fetched it (its tests/ too); fetched if missing."""
    return fetch_source(build_root())


def sources_line(files=None) -> str:
    """The one ``deb-src`` line the build fetches from: the pinned suite's ``main`` on the
    machine's own Debian mirror."""
    mirror = aptsources.debian_mirror(files)
    return f"deb-src [signed-by={DEBIAN_KEYRING}] {mirror} {DEBIAN_SUITE} main"


def fetch_source(root: Path) -> Path:
    src_root = root / "src"
    tree = _tree(root)
    if (tree / "ports" / "unix" / "Makefile").is_file():
        return tree
    apt = root / "apt"
    for sub in ("sources.list.d", "preferences.d", "state", "lists/partial", "cache/archives/partial"):
        safefs.make_folder(apt / sub, base=root)  # (a link on the way: refused)
    if not (apt / "status").is_file():
        safefs.fresh_file(apt / "status")
    line = sources_line()
    safefs.write_text(
        apt / "sources.list",
        "# Written by the interpreter build: the pinned source package's suite, on the Debian\n"
        "# mirror this machine's apt uses (or $DEBIAN_MIRROR). Only for `apt-get source`.\n" + line + "\n",
    )
    _log(f"apt-get update (project-local sources: {line})")
    subprocess.run(_apt(root, "update"), check=True, stdout=subprocess.DEVNULL)
    if src_root.is_symlink():
        safefs.refuse_link(src_root)
    if src_root.exists():
        shutil.rmtree(src_root)
    safefs.make_folder(src_root)
    _log(f"apt-get source micropython={DEBIAN_VERSION}")
    subprocess.run(
        _apt(root, "source", f"micropython={DEBIAN_VERSION}"), check=True, cwd=src_root, stdout=subprocess.DEVNULL
    )
    if not tree.is_dir():
        raise SetupError(f"apt-get source did not unpack {tree}")
    return tree


def find_variant(variant: str) -> Path:
    """A variant's interpreter: the standard one is :func:`find`; ``settrace`` is
    ``$MICROPYTHON_SETTRACE`` if set, else the one built (:func:`build_variant`), else a
    :class:`SetupError` naming the command that builds it."""
    if variant == "standard":
        return find()
    override = os.environ.get(f"MICROPYTHON_{variant.upper()}")
    if override:
        if not _executable(Path(override)):
            raise SetupError(f"MICROPYTHON_{variant.upper()}={override} is not an executable file")
        return Path(override)
    for path in dict.fromkeys((variant_path(variant), variant_path(variant, build_root(checkout=False)))):
        if _executable(path):
            return path
    raise SetupError(
        f"no {variant} interpreter (looked at $MICROPYTHON_{variant.upper()}, {variant_path(variant)}): "
        f"run `python3 -m host.core.interpreter build {variant}` (or ask for coverage: make hil COVERAGE=1)"
    )


def build_variant(variant: str, root: Path | None = None) -> Path:
    """Build a variant other than the standard one into ``root`` unless it is there (or
    ``$MICROPYTHON_<VARIANT>`` names it), one build at a time (a lock beside it)."""
    if variant == "standard":
        return build(root)
    override = os.environ.get(f"MICROPYTHON_{variant.upper()}")
    if override and root is None:
        return find_variant(variant)
    root = made_root(root or build_root())
    target = variant_path(variant, root)
    with safefs.open_write(root / f".{variant}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)  # (pytest workers, two make targets: one compiles)
        if current(target, variant):
            return target
        ensure_tools()
        _compile(fetch_source(root), root / f"build-{variant}.log", variant, target)
    return target


def _compile(tree: Path, log: Path, variant: str, target: Path) -> None:
    jobs = f"-j{os.cpu_count() or 2}"
    objects = tree / "ports" / "unix" / f"build-{variant}"
    _log(f"building the unix port ({variant} variant, asyncio frozen in); log: {log}")
    shutil.rmtree(objects, ignore_errors=True)
    patch_tree(tree)
    unix = ["make", jobs, "-C", str(tree / "ports" / "unix"), *map(_absolute, make_options(variant))]
    with safefs.open_write(log, "w") as out:
        for cmd in (["make", jobs, "-C", str(tree / "mpy-cross")], [*unix, f"FROZEN_MANIFEST={HERE / 'manifest.py'}"]):
            if subprocess.run(cmd, stdout=out, stderr=subprocess.STDOUT).returncode != 0:
                tail = log.read_text().splitlines()[-20:]
                raise SetupError(f"build failed: {' '.join(cmd)}\n" + "\n".join(tail) + f"\n(full log: {log})")
    tmp = safefs.fresh_file(target.with_suffix(".tmp"))  # (a link left there: removed, not written through)
    shutil.copy2(objects / "micropython", tmp)
    tmp.replace(target)
    if _in_checkout(target):
        safefs.write_text(_identity_file(target), identity(variant) + "\n")
    _log(f"built {target}: {version(target)}")


def build(root: Path | None = None) -> Path:
    """Build the interpreter into ``root`` (default :func:`build_root`) unless it is there."""
    root = made_root(root or build_root())
    target = default_path(root)
    if current(target, "standard"):
        _log(f"up to date: {target}")
        return target
    ensure_tools()
    safefs.make_folder(target.parent, base=root)
    _compile(fetch_source(root), root / "build.log", "standard", target)
    if _in_checkout(target):
        os.utime(_identity_file(target))
    os.utime(target)  # newer than its inputs, so make does not rebuild it
    return target


def setup(log=_log) -> Path:
    """``mpy-fil setup``: the interpreter the harness will run, got once. ``$MICROPYTHON``
    when set (checked), else one built before, else a ``micropython`` on ``PATH`` of the
    pinned version, else built from Debian's source into :func:`build_root`."""
    override = os.environ.get("MICROPYTHON")
    if override:
        path = find()
        problem = version_problem(path)
        if problem:
            raise SetupError(f"MICROPYTHON={override}: {problem}")
        log(f"using MICROPYTHON={path} (keep it set where the tests run)")
        return path
    if _executable(default_path()) and current(default_path(), "standard"):
        log(f"up to date: {default_path()}")
        return default_path()
    found = shutil.which("micropython")
    if found:
        problem = version_problem(Path(found))
        if problem is None:
            log(f"using {found} from PATH")
            return Path(found)
        log(f"not using the micropython on PATH: {problem}")
    return build()


def main(argv: list[str]) -> int:
    cmd = argv[0] if argv else "path"
    try:
        if cmd == "build":
            if len(argv) > 1:
                print(build_variant(argv[1]))
            else:
                build()
        elif cmd == "path":
            print(find())
        elif cmd == "version":
            path = find()
            print(f"{version(path)} ({path})")
        else:
            print("usage: python3 -m host.core.interpreter [build [VARIANT]|path|version]", file=sys.stderr)
            return 2
    except SetupError as e:
        print(f"error: {e}", file=sys.stderr)
        return 1
    except subprocess.CalledProcessError as e:
        print(f"error: {' '.join(map(str, e.cmd))} failed with exit code {e.returncode}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
