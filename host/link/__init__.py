"""The plant link, bytes only: a raw pty pair (:mod:`.pty`), a non-blocking transport
with deadlines (:mod:`.transport`), framed messages (:mod:`.channel`) and the codec shared
with the shim (:mod:`.frames`). Knows nothing of plants, pins or time."""

from host.link.channel import Channel
from host.link.pty import PtyPair
from host.link.transport import FdTransport, spare_core

__all__ = ["Channel", "FdTransport", "PtyPair", "spare_core"]
