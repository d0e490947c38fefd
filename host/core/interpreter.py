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
(``$XDG_CACHE_HOME/mpy-fil/micropython/<version>/<key>/``, ``~/.cache`` when unset), shared
by every project and virtual environment of that user, never inside ``site-packages``. In the
cache a version's binaries are keyed by their build (:func:`build_key`: the make options,
patches, frozen manifest and C modules), so two releases of the harness, or two checkouts
whose builds differ, never overwrite each other's binary.
``mpy-fil setup`` (:func:`setup`) takes ``$MICROPYTHON``, else one already built, else a
``micropython`` on ``PATH`` of the pinned version, else builds it.

Before make, the patches in ``host/core/micropython/*.patch`` are applied to the unpacked
source (:func:`patch_tree`): ``hilcount.patch`` makes the VM count what the firmware executes
(bytecodes by opcode, calls into C, allocations, collections) and keep a stack of the running
bytecode functions, for MCU time (docs/mcu-time.md); ``threadstate.patch`` reads the
thread's state (``MP_STATE_THREAD``, at every exception handler, stack check and collector
lock) from a thread-local variable, inline, instead of a call to ``pthread_getspecific``
(the unix port keeps ``_thread``, which a rig file may give back). The patches, the make
options (with :data:`TUNED_OPTIONS`) and the
frozen manifest make a build's identity (:func:`identity`), written beside each binary of a
checkout's build: a binary of another identity is rebuilt (:func:`current`), but never
under a running test session (:func:`_before_compile`: it names the inputs that changed).

Versions (:data:`RELEASES`, docs/versions.md): 1.25 (the default, Debian 13 "trixie"'s
source package), 1.26 (Debian's next release's source package, suite "forky"), 1.27 and 1.28
(MicroPython's own source at the release's tag, from a clone or a release tree the user names:
``$MICROPYTHON_SOURCE``, :func:`upstream_source`; no package registry carries them as source).
Which one runs: the ``version`` argument, else ``$MPY_FIL_MICROPYTHON`` (``[interpreter]
version`` of a rig file, ``pytest --mpy-version``), else :data:`DEFAULT_VERSION`. Each is built
into its own folder (``<root>/<build>/``, :func:`default_path`) with its own patches
(``host/core/micropython/<version>/*.patch``; 1.25's are ``host/core/micropython/*.patch``)
and its own identity; ``make setup`` builds the default one only.

A second variant, ``settrace`` (:func:`build_variant`): the same build with line tracing
(``sys.settrace``) for firmware coverage (docs/coverage.md), built only when coverage is
asked for, into its own objects (``build-settrace``) and binary (``micropython-settrace``
beside the standard one); ``$MICROPYTHON_SETTRACE`` overrides it. The standard build's
command and binary are untouched by it.
"""

import fcntl
import functools
import hashlib
import os
import shutil
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

from host.core import aptsources, paths, safefs
from host.core.errors import SetupError

DEBIAN_VERSION = "1.25.0+ds-1"
"""Pinned source package version (Debian 13 "trixie" carries 1.25.0)."""
DEBIAN_SUITE = "trixie"
DEBIAN_KEYRING = "/usr/share/keyrings/debian-archive-keyring.gpg"


@dataclass(frozen=True)
class Release:
    """A MicroPython version the harness builds: from Debian's source package ``debian`` (in
    ``suite``), or from MicroPython's own source at ``tag`` (:func:`upstream_source`)."""

    version: str  # what a rig file, `mpy-fil setup --micropython` and `pytest --mpy-version` say
    build: str  # the folder its binaries go to, below the build root
    debian: str | None = None
    suite: str | None = None
    tag: str | None = None


RELEASES = {
    r.version: r
    for r in (
        Release("1.25", DEBIAN_VERSION, debian=DEBIAN_VERSION, suite=DEBIAN_SUITE),
        Release("1.26", "1.26.1+ds-1", debian="1.26.1+ds-1", suite="forky"),
        Release("1.27", "1.27.0", tag="v1.27.0"),
        Release("1.28", "1.28.0", tag="v1.28.0"),
    )
}
"""The versions the harness builds (docs/versions.md: where each comes from, how one is added)."""
DEFAULT_VERSION = "1.25"
VERSION_ENV = "MPY_FIL_MICROPYTHON"
"""The version selected for this process and the runs it starts (set by ``[interpreter]
version`` and ``pytest --mpy-version``)."""
SOURCE_ENV = "MICROPYTHON_SOURCE"
"""MicroPython's source for a version Debian does not carry: a git repository (a clone, or a
bare one) holding the release's tag, or the release's unpacked tree."""


def release(version: str | None = None) -> Release:
    """The release of ``version`` ("1.28" or "1.28.0"), else of ``$MPY_FIL_MICROPYTHON``,
    else the default; a :class:`SetupError` naming the known ones for another."""
    asked = (version or os.environ.get(VERSION_ENV) or DEFAULT_VERSION).strip()
    key = ".".join(asked.lstrip("v").split("+")[0].split(".")[:2])
    if key not in RELEASES:
        raise SetupError(f"no MicroPython {asked} in the harness: expected one of {', '.join(RELEASES)}")
    return RELEASES[key]


def selected(version: str | None = None) -> bool:
    """A version was asked for (argument or ``$MPY_FIL_MICROPYTHON``), not the default by
    default: then ``$MICROPYTHON`` is used only when it is of that version."""
    return bool(version or os.environ.get(VERSION_ENV))


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
TUNED_OPTIONS = {
    "1.25": ("COPT=-O2 -DNDEBUG -fdata-sections -ffunction-sections -DMICROPY_OPT_MAP_LOOKUP_CACHE_SIZE=4096",),
}
"""Options measured to make a version's interpreter faster (docs/bench.md, "The interpreter
we build"): -O2 where the port has -Os, and a map lookup cache of 4096 entries where
py/mpconfig.h has 128 (it remembers where a name was last found in a dict, a module's or a
class's; 128 entries, shared by every name the shim and the firmware look up, kept few of
them). The port's own ``COPT`` with its optimisation level replaced; the rest
(``-DNDEBUG``, sections for ``--gc-sections``) as the port has it. None changes what a
program does, nor how deep it may recurse (link-time optimisation, faster still, made the
VM's C frames larger and the recursion limit lower: left out). A version not measured
keeps the port's options."""
VARIANT_OPTIONS = {
    "standard": (),
    # line tracing (py/profile.c; it implies MICROPY_PERSISTENT_CODE_SAVE), objects of its own
    "settrace": ("CFLAGS_EXTRA=-DMICROPY_PY_SYS_SETTRACE=1", "BUILD=build-settrace"),
}
"""What each variant adds to :data:`MAKE_OPTIONS` (its make command: :func:`make_options`)."""
PROJECT_ROOT = HERE.parent.parent.parent
"""What a relative folder in :data:`MAKE_OPTIONS` is relative to."""


def patches(version: str | None = None) -> tuple[Path, ...]:
    """A version's patches: ``host/core/micropython/<version>/*.patch``, the default version's
    in ``host/core/micropython/`` itself."""
    folder = HERE / release(version).version
    return tuple(sorted((folder if folder.is_dir() else HERE).glob("*.patch")))


PATCHES = patches(DEFAULT_VERSION)
"""The default version's, applied in order to the unpacked source before make (``patch -p1``)."""
APPLIED = ".mpy-fil-applied.patch"
"""In the source tree: the patches' text as last applied (:func:`patch_tree`)."""


def patches_text(version: str | None = None) -> str:
    return "".join(p.read_text() for p in patches(version))


def _inputs(variant: str, version: str | None) -> list[tuple[str, bytes]]:
    """What a build is made of, each input named: its source's version and make options, the
    patches, the frozen manifest and each file of the user C modules."""
    rel = release(version)
    made = [("options", rel.build.encode() + b"\0" + "\0".join(make_options(variant, rel.version)).encode() + b"\0")]
    made += [("patches", patches_text(rel.version).encode()), ("manifest.py", (HERE / "manifest.py").read_bytes())]
    cmod = PROJECT_ROOT / "host" / "shim" / "cmod"
    for f in sorted(cmod.rglob("*")):
        if f.is_file():
            made.append((f"cmod/{f.relative_to(cmod)}", str(f.relative_to(cmod)).encode() + b"\0" + f.read_bytes()))
    return made


def identity(variant: str = "standard", version: str | None = None) -> str:
    """What a build is made of: a hash of its source's version, make options, the patches,
    the frozen manifest and the user C modules' files (:func:`_inputs`). Written beside the
    binary (``<binary>.identity``, its first line; then each input's own hash, so that a
    binary found out of date can say which input changed: :func:`changed_inputs`)."""
    h = hashlib.sha256()
    for _, data in _inputs(variant, version):
        h.update(data)
    return h.hexdigest()[:16]


def _identity_text(variant: str, version: str | None) -> str:
    lines = [identity(variant, version)]
    lines += [f"{hashlib.sha256(data).hexdigest()[:16]} {name}" for name, data in _inputs(variant, version)]
    return "\n".join(lines) + "\n"


def changed_inputs(target: Path, variant: str, version: str | None = None) -> list[str]:
    """The inputs of the build at ``target`` (a checkout's) that differ from the tree's now:
    named from its identity file, or why they cannot be ("no binary", "no identity file")."""
    if not Path(target).is_file():
        return ["no binary"]
    marker = _identity_file(target)
    if not marker.is_file():
        return ["no identity file"]
    recorded = dict(line.split(" ", 1)[::-1] for line in marker.read_text().splitlines()[1:] if " " in line)
    now = {name: hashlib.sha256(data).hexdigest()[:16] for name, data in _inputs(variant, version)}
    if not recorded:
        return ["inputs not recorded (an identity file of an older harness)"]
    return sorted(n for n in now.keys() | recorded.keys() if now.get(n) != recorded.get(n))


def build_key(version: str | None = None) -> str:
    """What the per-user cache keys a version's binaries by (``<version>/<key>/``): the
    identities of all its variants (:func:`identity`: the version's source, make options,
    patches, frozen manifest and user C modules)."""
    rel = release(version)
    whole = "\0".join(identity(v, rel.version) for v in VARIANT_OPTIONS)
    return hashlib.sha256(whole.encode()).hexdigest()[:16]


def _identity_file(target: Path) -> Path:
    return target.with_name(target.name + ".identity")


def _in_checkout(target: Path) -> bool:
    return paths.CHECKOUT and Path(target).is_relative_to(build_root(checkout=True))


def current(target: Path, variant: str, version: str | None = None) -> bool:
    """The binary at ``target`` is there and, in a checkout's build/ (where the patches and
    the C modules change under it), of this build's identity. (In the per-user cache the
    folder's name is the build's key, :func:`build_key`: a binary there is this build's.)"""
    if not target.is_file():
        return False
    if not _in_checkout(target):
        return True
    marker = _identity_file(target)
    return marker.is_file() and marker.read_text().partition("\n")[0].strip() == identity(variant, version)


BUILD_LOG = "builds.log"
"""In a build folder: a line for each compile (when, which binary, what changed, who asked)."""


def _before_compile(root: Path, target: Path, variant: str, version: str | None) -> None:
    """Say in the build folder's :data:`BUILD_LOG` who compiles ``target`` and why; refuse
    to rebuild a checkout's binary that is there while a test session runs (``make test``
    built it first; rebuilding it would take it from under the session's other workers,
    which then find no interpreter): the error names the inputs that changed."""
    why = ", ".join(changed_inputs(target, variant, version)) if _in_checkout(target) else "not built"
    test = os.environ.get("PYTEST_CURRENT_TEST", "")
    line = f"{time.strftime('%Y-%m-%dT%H:%M:%S')} pid {os.getpid()} {target.name}: {why}; {' '.join(sys.argv)}"
    with safefs.open_write(root / BUILD_LOG, "a") as log:
        log.write(line + (f"; test {test}" if test else "") + "\n")
    if test and _in_checkout(target) and target.is_file():
        raise SetupError(
            f"{target} is out of date ({why} changed since it was built) and a test session is "
            f"running on it: run `make setup` before the tests (a test does not rebuild it; "
            f"its build log: {root / BUILD_LOG})"
        )


def patch_tree(tree: Path, version: str | None = None) -> None:
    """Apply the version's patches (:func:`patches`) to the source tree, once: a tree patched
    with other text is first unpatched (``patch -R`` with the text recorded in :data:`APPLIED`)."""
    want = patches_text(version)
    applied = tree / APPLIED
    have = applied.read_text() if applied.is_file() else ""
    if have == want:
        return
    if have:
        _log("unpatching the source (the patches changed)")
        _patch(tree, have, "-R")
        applied.unlink()
    if want:
        _log("patching the source: " + ", ".join(paths.portable(p) for p in patches(version)))
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


def default_path(root: Path | None = None, version: str | None = None) -> Path:
    """The built binary: ``<root>/<build>/micropython`` in a checkout's own build folder
    (``1.25.0+ds-1``, ``1.28.0``: the version's :attr:`Release.build`; rebuilt there when its
    identity changes), ``<root>/<build>/<key>/micropython`` in any other (the per-user cache:
    one folder per :func:`build_key`, each build beside the others)."""
    root = Path(root or build_root())
    folder = root / release(version).build
    if not (paths.CHECKOUT and root == build_root(checkout=True)):
        folder = folder / build_key(version)
    return folder / "micropython"


def variant_path(variant: str, root: Path | None = None, version: str | None = None) -> Path:
    """A variant's binary: the standard one at :func:`default_path`, another beside it
    (``micropython-<variant>``)."""
    if variant not in VARIANT_OPTIONS:
        raise SetupError(f"no interpreter variant {variant!r}: expected one of {', '.join(VARIANT_OPTIONS)}")
    target = default_path(root, version)
    return target if variant == "standard" else target.with_name(f"micropython-{variant}")


UPSTREAM_OPTIONS = ("MPY_LIB_DIR=$(TOP)/lib",)
"""Added for a build from MicroPython's own source: py/mkrules.mk refuses to freeze a manifest
without ``$(MPY_LIB_DIR)/README.md`` (the micropython-lib submodule, which a tag's archive
leaves empty); the frozen manifest takes nothing from it, so lib/ (whose README.md is there)
stands in. Debian's package drops that check (its patch 0007)."""


def make_options(variant: str = "standard", version: str | None = None) -> tuple[str, ...]:
    """The unix port's make options of a variant (without the frozen manifest)."""
    rel = release(version)
    upstream = UPSTREAM_OPTIONS if rel.tag else ()
    return (*MAKE_OPTIONS, *TUNED_OPTIONS.get(rel.version, ()), *upstream, *VARIANT_OPTIONS[variant])


def _executable(path: Path) -> bool:
    return path.is_file() and os.access(path, os.X_OK)


def on_path(version: str | None = None) -> Path | None:
    """A ``micropython`` on ``PATH`` of the selected version (major.minor), or None."""
    found = shutil.which("micropython")
    if found is None:
        return None
    return Path(found) if version_problem(Path(found), version) is None else None


def version_problem(path: Path, version: str | None = None) -> str | None:
    """Why the interpreter at ``path`` will not do (not the selected MicroPython version),
    or None when it will."""
    want = release(version).version  # "1.25"
    try:
        line = _version_of(str(path), _mtime(path))
    except (OSError, subprocess.SubprocessError) as e:
        return f"{path} does not run as MicroPython ({e})"
    if not line.startswith(f"MicroPython v{want}."):
        return f"{path} is {line or 'of no known version'}; the harness needs MicroPython {want}"
    return None


def _mtime(path: Path) -> int:
    try:
        return Path(path).stat().st_mtime_ns
    except OSError:
        return 0


@functools.cache
def _version_of(path: str, mtime_ns: int) -> str:
    return version(Path(path))


def _override(name: str, version: str | None) -> Path | None:
    """``$MICROPYTHON`` (or a variant's): used when no version was asked for, or when it is
    of the version asked for (``pytest --mpy-version 1.25,1.28`` with it set to a 1.25)."""
    override = os.environ.get(name)
    if not override:
        return None
    if selected(version) and (not _executable(Path(override)) or version_problem(Path(override), version)):
        return None  # (not that version's: the build of the version asked for is looked for)
    if not _executable(Path(override)):
        raise SetupError(f"{name}={override} is not an executable file")
    return Path(override)


def setup_hint(version: str | None = None) -> str:
    rel = release(version)
    if rel.version == DEFAULT_VERSION and not selected(version):
        return SETUP_HINT
    return f"run `mpy-fil setup --micropython {rel.version}`"


def find(version: str | None = None) -> Path:
    """The interpreter to run: ``$MICROPYTHON`` if set (and of the version asked for, when
    one is), else the one built by setup, else one on ``PATH`` of the selected version. A
    :class:`SetupError` that says the one command to run when there is none."""
    override = _override("MICROPYTHON", version)
    if override:
        return override
    for path in _built("standard", version):
        if _executable(path):
            return path
    found = on_path(version)
    if found is not None:
        return found
    raise SetupError(
        f"no MicroPython {release(version).version} interpreter (looked at $MICROPYTHON, "
        f"{default_path(None, version)}, PATH): {setup_hint(version)}"
    )


def _built(variant: str, version: str | None):
    """Where a variant's binary may be: the build folder's, then the per-user cache's (of
    this build's key: another build's binary is never taken)."""
    yield variant_path(variant, None, version)
    if paths.CHECKOUT:
        yield variant_path(variant, build_root(checkout=False), version)


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


def _apt_dir(root: Path, suite: str = DEBIAN_SUITE) -> Path:
    """The project-local apt folder of a suite (the pinned one's: ``apt``, as it always was)."""
    return root / ("apt" if suite == DEBIAN_SUITE else f"apt-{suite}")


def _apt(root: Path, *args: str, suite: str = DEBIAN_SUITE) -> list[str]:
    apt = _apt_dir(root, suite)
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


def _src_root(root: Path, version: str | None = None) -> Path:
    rel = release(version)
    return root / ("src" if rel.version == DEFAULT_VERSION else f"src-{rel.build}")


def _tree(root: Path, version: str | None = None) -> Path:
    rel = release(version)
    name = rel.debian.rsplit("-", 1)[0] if rel.debian else rel.build
    return _src_root(root, version) / f"micropython-{name}"


def source_tree(version: str | None = None) -> Path:
    """MicroPython's source as the build fetched it (its tests/ too); fetched if missing."""
    return fetch_source(build_root(), version)


def sources_line(files=None, suite: str = DEBIAN_SUITE) -> str:
    """The one ``deb-src`` line the build fetches from: the suite's ``main`` on the
    machine's own Debian mirror."""
    mirror = aptsources.debian_mirror(files)
    return f"deb-src [signed-by={DEBIAN_KEYRING}] {mirror} {suite} main"


def upstream_source(source: str | None = None) -> Path:
    """Where MicroPython's own source is (``source``, else ``$MICROPYTHON_SOURCE``): a git
    repository or a release's unpacked tree; a :class:`SetupError` saying how to get one."""
    given = source or os.environ.get(SOURCE_ENV)
    if not given:
        raise SetupError(
            "this MicroPython version is built from MicroPython's own source (micropython/micropython "
            "on GitHub; no package registry carries it as source): clone it and set "
            f"{SOURCE_ENV}=<the clone> (or pass --source <the clone>) (docs/versions.md)"
        )
    path = Path(given).expanduser().resolve()
    if not path.is_dir():
        raise SetupError(f"{SOURCE_ENV}={given}: not a folder")
    return path


def _is_git(path: Path) -> bool:
    return (path / ".git").exists() or ((path / "HEAD").is_file() and (path / "objects").is_dir())


def _tree_version(tree: Path) -> str:
    """``1.28.0`` from a tree's py/mpconfig.h (its MICROPY_VERSION_MAJOR/MINOR/MICRO)."""
    import re

    text = (tree / "py" / "mpconfig.h").read_text(errors="replace")
    parts = [re.search(rf"#define MICROPY_VERSION_{k} \((\d+)\)", text) for k in ("MAJOR", "MINOR", "MICRO")]
    return ".".join(m.group(1) for m in parts) if all(parts) else "unknown"


def _unpack_upstream(rel: Release, tree: Path, source: str | None) -> None:
    """The release's tag from a git repository (``git archive``; no work tree needed, a bare
    mirror will do), or a copy of a release tree of that version."""
    src = upstream_source(source)
    tmp = tree.with_name(tree.name + ".tmp")
    shutil.rmtree(tmp, ignore_errors=True)
    safefs.make_folder(tmp)
    if _is_git(src):
        git = ["git", "-C", str(src)]
        tag = f"{rel.tag}^{{commit}}"
        commit = subprocess.run([*git, "rev-parse", "--verify", tag], capture_output=True, text=True)
        if commit.returncode != 0:
            raise SetupError(f"{src} has no tag {rel.tag} (fetch the tags: git -C {src} fetch --tags)")
        _log(f"git archive {rel.tag} ({commit.stdout.strip()[:10]}) from {src}")
        archive = subprocess.Popen([*git, "archive", rel.tag], stdout=subprocess.PIPE)
        untar = subprocess.run(["tar", "-x", "-C", str(tmp)], stdin=archive.stdout)
        archive.stdout.close()
        if archive.wait() != 0 or untar.returncode != 0:
            raise SetupError(f"git archive {rel.tag} from {src} failed")
        safefs.write_text(tmp / ".mpy-fil-commit", commit.stdout.strip() + "\n")
    else:
        have = _tree_version(src) if (src / "py" / "mpconfig.h").is_file() else "not a MicroPython tree"
        if have != rel.tag.lstrip("v"):
            want = rel.tag.lstrip("v")
            raise SetupError(f"{src}: MicroPython {have}, not {want} (a clone will do: docs/versions.md)")
        _log(f"copying the release tree {src}")
        shutil.rmtree(tmp)
        shutil.copytree(src, tmp, symlinks=True, ignore=shutil.ignore_patterns("build-*", ".git"))
    tmp.replace(tree)


def build_env(tree: Path, version: str | None = None) -> dict:
    """The environment make runs in. For MicroPython's own source, the version its header
    gets (py/makeversionhdr.py, make_version_header: ``$MICROPY_GIT_TAG`` first; else it runs
    ``git describe`` wherever the tree is, which names the repository around build/)."""
    rel = release(version)
    if not rel.tag:
        return dict(os.environ)
    marker = tree / ".mpy-fil-commit"
    commit = marker.read_text().strip()[:10] if marker.is_file() else "release tree"
    return {**os.environ, "MICROPY_GIT_TAG": rel.tag, "MICROPY_GIT_HASH": commit}


def fetch_source(root: Path, version: str | None = None, source: str | None = None) -> Path:
    rel = release(version)
    src_root = _src_root(root, rel.version)
    tree = _tree(root, rel.version)
    if (tree / "ports" / "unix" / "Makefile").is_file():
        return tree
    if rel.tag:
        safefs.make_folder(src_root, base=root)
        _unpack_upstream(rel, tree, source)
        return tree
    apt = _apt_dir(root, rel.suite)
    for sub in ("sources.list.d", "preferences.d", "state", "lists/partial", "cache/archives/partial"):
        safefs.make_folder(apt / sub, base=root)  # (a link on the way: refused)
    if not (apt / "status").is_file():
        safefs.fresh_file(apt / "status")
    line = sources_line(suite=rel.suite)
    safefs.write_text(
        apt / "sources.list",
        "# Written by the interpreter build: the source package's suite, on the Debian\n"
        "# mirror this machine's apt uses (or $DEBIAN_MIRROR). Only for `apt-get source`.\n" + line + "\n",
    )
    _log(f"apt-get update (project-local sources: {line})")
    subprocess.run(_apt(root, "update", suite=rel.suite), check=True, stdout=subprocess.DEVNULL)
    if src_root.is_symlink():
        safefs.refuse_link(src_root)
    if src_root.exists():
        shutil.rmtree(src_root)
    safefs.make_folder(src_root)
    _log(f"apt-get source micropython={rel.debian}")
    subprocess.run(
        _apt(root, "source", f"micropython={rel.debian}", suite=rel.suite),
        check=True,
        cwd=src_root,
        stdout=subprocess.DEVNULL,
    )
    if not tree.is_dir():
        raise SetupError(f"apt-get source did not unpack {tree}")
    return tree


def find_variant(variant: str, version: str | None = None) -> Path:
    """A variant's interpreter: the standard one is :func:`find`; ``settrace`` is
    ``$MICROPYTHON_SETTRACE`` if set (and of the version asked for, when one is), else the
    one built (:func:`build_variant`), else a :class:`SetupError` naming the command that
    builds it."""
    if variant == "standard":
        return find(version)
    override = _override(f"MICROPYTHON_{variant.upper()}", version)
    if override:
        return override
    for path in _built(variant, version):
        if _executable(path):
            return path
    asked = f" --micropython {release(version).version}" if selected(version) else ""
    raise SetupError(
        f"no {variant} interpreter (looked at $MICROPYTHON_{variant.upper()}, {variant_path(variant, None, version)}): "
        f"run `python3 -m host.core.interpreter build {variant}{asked}` (or ask for coverage: make hil COVERAGE=1)"
    )


def build_variant(
    variant: str, root: Path | None = None, version: str | None = None, source: str | None = None
) -> Path:
    """Build a variant other than the standard one into ``root`` unless it is there (or
    ``$MICROPYTHON_<VARIANT>`` names it), one build at a time (a lock beside it)."""
    if variant == "standard":
        return build(root, version, source)
    if root is None and _override(f"MICROPYTHON_{variant.upper()}", version):
        return find_variant(variant, version)
    rel = release(version)
    root = made_root(root or build_root())
    target = variant_path(variant, root, rel.version)
    with safefs.open_write(root / _lock_name(rel), "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)  # (pytest workers, two make targets: one compiles)
        if current(target, variant, rel.version):
            return target
        _before_compile(root, target, variant, rel.version)
        ensure_tools()
        safefs.make_folder(target.parent, base=root)
        tree = fetch_source(root, rel.version, source)
        _compile(tree, root / f"build-{variant}-{rel.build}.log", variant, target, rel.version)
    return target


def _lock_name(rel: Release) -> str:
    """One lock per version in a build folder, for every variant and build key: they share
    the version's source tree, which each build patches as its own."""
    return f".build-{rel.build}.lock"


def _compile(tree: Path, log: Path, variant: str, target: Path, version: str | None = None) -> None:
    jobs = f"-j{os.cpu_count() or 2}"
    objects = tree / "ports" / "unix" / f"build-{variant}"
    what = f"MicroPython {release(version).build}, {variant} variant, asyncio frozen in"
    _log(f"building the unix port ({what}); log: {log}")
    shutil.rmtree(objects, ignore_errors=True)
    patch_tree(tree, version)
    unix = ["make", jobs, "-C", str(tree / "ports" / "unix"), *map(_absolute, make_options(variant, version))]
    env = build_env(tree, version)
    with safefs.open_write(log, "w") as out:
        for cmd in (["make", jobs, "-C", str(tree / "mpy-cross")], [*unix, f"FROZEN_MANIFEST={HERE / 'manifest.py'}"]):
            if subprocess.run(cmd, stdout=out, stderr=subprocess.STDOUT, env=env).returncode != 0:
                tail = log.read_text().splitlines()[-20:]
                raise SetupError(f"build failed: {' '.join(cmd)}\n" + "\n".join(tail) + f"\n(full log: {log})")
    tmp = safefs.fresh_file(target.with_suffix(".tmp"))  # (a link left there: removed, not written through)
    shutil.copy2(objects / "micropython", tmp)
    tmp.replace(target)
    if _in_checkout(target):
        safefs.write_text(_identity_file(target), _identity_text(variant, version))
    _log(f"built {target}: {version_line(target)}")


def version_line(path: Path) -> str:
    """:func:`version`, asked once per binary (path and modification time)."""
    return _version_of(str(path), _mtime(path))


def build(root: Path | None = None, version: str | None = None, source: str | None = None) -> Path:
    """Build the interpreter of ``version`` into ``root`` (default :func:`build_root`) unless
    it is there."""
    rel = release(version)
    root = made_root(root or build_root())
    target = default_path(root, rel.version)
    if current(target, "standard", rel.version):
        _log(f"up to date: {target}")
        return target
    with safefs.open_write(root / _lock_name(rel), "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)  # (two setups of one version: one compiles, in one tree)
        if current(target, "standard", rel.version):
            _log(f"up to date: {target}")
            return target
        _before_compile(root, target, "standard", rel.version)
        ensure_tools()
        safefs.make_folder(target.parent, base=root)
        log = root / ("build.log" if rel.version == DEFAULT_VERSION else f"build-{rel.build}.log")
        _compile(fetch_source(root, rel.version, source), log, "standard", target, rel.version)
        if _in_checkout(target):
            os.utime(_identity_file(target))
        os.utime(target)  # newer than its inputs, so make does not rebuild it
    return target


def setup(log=_log, version: str | None = None, source: str | None = None) -> Path:
    """``mpy-fil setup [--micropython VERSION]``: the interpreter the harness will run, got
    once. ``$MICROPYTHON`` when set (checked: of the version asked for), else one built
    before, else a ``micropython`` on ``PATH`` of that version, else built (from Debian's
    source, or MicroPython's own for a version Debian does not carry) into :func:`build_root`."""
    rel = release(version)
    override = os.environ.get("MICROPYTHON")
    if override:
        problem = version_problem(Path(override), rel.version) if _executable(Path(override)) else "not executable"
        if problem is None:
            log(f"using MICROPYTHON={override} (keep it set where the tests run)")
            return Path(override)
        if not selected(version):
            raise SetupError(f"MICROPYTHON={override}: {problem}")
        log(f"not using MICROPYTHON={override} for MicroPython {rel.version}: {problem}")
    target = default_path(None, rel.version)
    if _executable(target) and current(target, "standard", rel.version):
        log(f"up to date: {target}")
        return target
    found = shutil.which("micropython")
    if found:
        problem = version_problem(Path(found), rel.version)
        if problem is None:
            log(f"using {found} from PATH")
            return Path(found)
        log(f"not using the micropython on PATH: {problem}")
    return build(None, rel.version, source)


USAGE = (
    "usage: python3 -m host.core.interpreter [build [VARIANT]|path|version|versions] "
    "[--micropython VERSION] [--source DIR]"
)


def main(argv: list[str]) -> int:
    args, version, source = [], None, None
    it = iter(argv)
    for a in it:
        if a in ("--micropython", "--source"):
            value = next(it, None)
            if value is None:
                print(USAGE, file=sys.stderr)
                return 2
            version, source = (value, source) if a == "--micropython" else (version, value)
        else:
            args.append(a)
    cmd = args[0] if args else "path"
    try:
        if cmd == "build":
            if len(args) > 1:
                print(build_variant(args[1], None, version, source))
            else:
                build(None, version, source)
        elif cmd == "path":
            print(find(version))
        elif cmd == "version":
            path = find(version)
            print(f"{version_line(path)} ({path})")
        elif cmd == "versions":
            for rel in RELEASES.values():
                where = f"Debian {rel.debian} ({rel.suite})" if rel.debian else f"MicroPython's source, tag {rel.tag}"
                built = default_path(None, rel.version)
                state = "built" if _executable(built) else "not built"
                mark = " (default)" if rel.version == DEFAULT_VERSION else ""
                print(f"{rel.version}{mark}: {where}; {state}: {built}")
        else:
            print(USAGE, file=sys.stderr)
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
