"""The published MicroPython drivers the tests run unchanged (``host/core/drivers.txt``):
fetched by ``make setup`` with the venv's pip (``pip download --no-deps --require-hashes``,
pinned by version and hash) into ``build/drivers/``, each unpacked into its own folder, a
firmware's library folder (``driver_folder``). Never copied into the repository.

A project whose sdist pip cannot prepare (no ``setup.py``: ``micropython-ssd1306``, in
``AS_FILES``) is fetched as a file: its sdist found on the index pip is configured with (the
simple API, PEP 691), and its hash checked here, as pip checks the others.

``python -m host.core.drivers`` fetches what is missing.
"""

import hashlib
import json
import os
import subprocess
import sys
import tarfile
import urllib.parse
import urllib.request
import zipfile
from pathlib import Path

from host.core.children import popen_options
from host.core.errors import HarnessError

ROOT = Path(__file__).resolve().parents[2]
LIST = Path(__file__).with_name("drivers.txt")
FOLDER = ROOT / "build" / "drivers"


class DriverMissing(HarnessError):
    """A pinned driver is not in build/drivers/ (``make setup`` fetches it)."""


def pinned() -> dict[str, str]:
    """Project name -> its pinned version, from the list."""
    out = {}
    for line in LIST.read_text().splitlines():
        line = line.split("#", 1)[0].strip()
        if line:
            name, _, rest = line.partition("==")
            out[name] = rest.split()[0]
    return out


AS_FILES = {"micropython-ssd1306", "micropython-bme280"}  # sdists without setup.py: pip cannot prepare them


def _as_file(line: str) -> tuple[str, str, str] | None:
    """(name, version, sha256) of a line whose project is fetched as a file, else None."""
    name, _, rest = line.partition("==")
    if name.strip() not in AS_FILES:
        return None
    return name.strip(), rest.split()[0], line.rpartition("--hash=sha256:")[2].split()[0]


def index_url() -> str:
    """The index pip is configured with (``pip config``, ``PIP_INDEX_URL``), else pip's own default."""
    done = subprocess.run(
        [sys.executable, "-m", "pip", "config", "get", "global.index-url"], capture_output=True, text=True
    )
    configured = os.environ.get("PIP_INDEX_URL") or (done.stdout.strip() if done.returncode == 0 else "")
    if configured:
        return configured.rstrip("/")
    from pip._internal.models.index import PyPI  # (pip's default index: named by pip, not here)

    return PyPI.simple_url.rstrip("/")


def driver_folder(name: str) -> Path:
    """The unpacked driver ``name`` (a project name of the list): a folder of modules."""
    folder = FOLDER / f"{name}-{pinned()[name]}"
    if not (folder / ".unpacked").exists():
        raise DriverMissing(f"expected the driver {name} unpacked in {folder}; got nothing there: run make setup")
    return folder


def fetch() -> None:
    """Download what the list pins (hashes checked by pip) and unpack each archive."""
    download = FOLDER / "download"
    download.mkdir(parents=True, exist_ok=True)
    command = [sys.executable, "-m", "pip", "download", "--no-deps", "--require-hashes", "-q"]
    lines = [line.split("#", 1)[0].strip() for line in LIST.read_text().splitlines()]
    for name, version, digest in filter(None, map(_as_file, lines)):
        _download(name, version, digest, download)
    requirements = download / "pip-requirements.txt"
    requirements.write_text("".join(line + "\n" for line in lines if line and not _as_file(line)))
    command += ["-r", str(requirements), "-d", str(download)]
    done = subprocess.run(command, capture_output=True, text=True, **popen_options())
    if done.returncode:
        raise HarnessError(f"pip download of {LIST} failed (exit {done.returncode}): {done.stderr.strip()[-600:]}")
    for name, version in pinned().items():
        _unpack(download, name, version)


def _download(name: str, version: str, digest: str, download: Path) -> None:
    """The sdist of ``name`` ``version`` from the index's simple API, checked against ``digest``."""
    filename = f"{name}-{version}.tar.gz"
    target = download / filename
    if target.exists() and hashlib.sha256(target.read_bytes()).hexdigest() == digest:
        return
    page = f"{index_url()}/{name}/"
    try:
        request = urllib.request.Request(page, headers={"Accept": "application/vnd.pypi.simple.v1+json"})
        with urllib.request.urlopen(request, timeout=60) as response:
            files = json.load(response)["files"]
        url = next(f["url"] for f in files if f["filename"] == filename)
        with urllib.request.urlopen(urllib.parse.urljoin(page, url), timeout=60) as response:
            data = response.read()
    except (OSError, ValueError, KeyError, StopIteration) as e:
        raise HarnessError(f"download of {filename} from {page} (pinned in {LIST}) failed: {e!r}") from None
    got = hashlib.sha256(data).hexdigest()
    if got != digest:
        raise HarnessError(f"{filename}: expected sha256 {digest} as {LIST} pins, got {got}")
    target.write_bytes(data)


def _unpack(download: Path, name: str, version: str) -> None:
    folder = FOLDER / f"{name}-{version}"
    if (folder / ".unpacked").exists():
        return
    stem = name.replace("-", "_").lower()  # (a wheel keeps the project's own case: KitronikPico...)
    archives = [p for p in download.iterdir() if p.name.replace("-", "_").lower().startswith(f"{stem}_{version}")]
    if not archives:
        raise HarnessError(f"expected {name} {version} in {download}, got {sorted(p.name for p in download.iterdir())}")
    folder.mkdir(parents=True, exist_ok=True)
    archive = archives[0]
    if archive.suffix == ".whl":
        with zipfile.ZipFile(archive) as z:
            members = [m for m in z.namelist() if ".dist-info/" not in m]
            z.extractall(folder, members)
    else:  # an sdist: its modules, from the top folder
        with tarfile.open(archive) as t:
            for member in t.getmembers():
                parts = Path(member.name).parts
                if member.isfile() and len(parts) == 2 and parts[1].endswith(".py") and parts[1] != "setup.py":
                    member.name = parts[1]
                    t.extract(member, folder, filter="data")
    (folder / ".unpacked").write_text(archive.name + "\n")


if __name__ == "__main__":
    try:
        fetch()
    except HarnessError as e:
        print(e, file=sys.stderr)
        sys.exit(2)
