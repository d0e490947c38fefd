"""A rig run from a flashed board folder (``make hil FIRMWARE=build/vboard/<board>/fs``)
against the app's sources: the flash holds the same code compiled (``.mpy``), so the link
trace is the sources' but for its header's ``firmware`` (the flashed folder and the digest of
its files). :func:`as_from_sources` puts the sources' identity there, so a pinned digest or a
trace of the sources can be compared with the flashed run's."""

import json

from host.core import paths
from host.rig import Rig


def ran_from_flash(rig) -> bool:
    """The rig ran a flashed board folder, not its app's sources."""
    return rig.spec.firmware_dir is not None


def as_from_sources(trace: bytes, rig) -> bytes:
    """``trace`` (the rig's ``trace.jsonl``) with its header's firmware that of the app's
    sources, when the rig ran from a flash; as it is otherwise. Only the header changes: every
    record after it must be the sources' for a pinned digest to match."""
    if not ran_from_flash(rig):
        return trace
    first, rest = trace.split(b"\n", 1)
    header = json.loads(first)
    flashed = header["header"]["firmware"]
    assert flashed["folder"] == paths.portable(rig.spec.firmware_dir), f"expected the flashed folder, got {flashed}"
    sources = Rig(rig.spec.replace(firmware_dir=None)).firmware.identity()
    sources["folder"] = paths.portable(sources["folder"])
    assert flashed["sha256"] != sources["sha256"], "expected the flashed files (.mpy) to differ from the sources"
    header["header"]["firmware"] = sources
    encode = json.JSONEncoder(separators=(",", ":"), sort_keys=True).encode  # (as host/artefacts/linklog.py)
    return encode(header).encode() + b"\n" + rest
