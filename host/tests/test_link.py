"""The host's end of the link: a raw pty, read with or without busy polling."""

import os

import pytest

from host.link import FdTransport, PtyPair


@pytest.mark.parametrize("busy_poll_s", [0.0, 0.05])
def test_console_written_before_link_bytes_is_read_with_them(busy_poll_s):
    """The firmware prints, then sends a frame: the host sees the console text by the
    time it reads the frame, whether it slept in select() or polled in a loop."""
    pty = PtyPair()
    console_r, console_w = os.pipe()
    slave = os.open(pty.slave_path, os.O_RDWR | os.O_NOCTTY)
    try:
        transport = FdTransport(pty.master_fd, busy_poll_s=busy_poll_s)
        seen = []
        transport.watch(console_r, seen.append)
        assert transport.read_some(0.01) == b"", "nothing sent yet: the read times out empty"
        os.write(console_w, b"hello from main.py\n")
        os.write(slave, b"\xa5frame")
        got = b""
        while len(got) < 6:
            got += transport.read_some(1.0)
        assert got == b"\xa5frame"
        assert b"".join(seen) == b"hello from main.py\n"
    finally:
        os.close(slave)
        os.close(console_r)
        os.close(console_w)
        pty.close()
