"""A pseudo-terminal pair in raw mode: the wire between the host and the unix port."""

import os
import termios
import tty


def _raw(fd: int, vmin: int = 0) -> None:
    tty.setraw(fd)
    attrs = termios.tcgetattr(fd)
    attrs[6][termios.VMIN] = vmin  # 0: reads return what is there (MicroPython's read(n)
    attrs[6][termios.VTIME] = 0  # would otherwise block until all n bytes arrive)
    termios.tcsetattr(fd, termios.TCSANOW, attrs)


class PtyPair:
    """A pseudo-terminal pair in raw mode; the firmware opens ``slave_path``.

    ``console=True`` makes the slave a board console instead of a link: blocking
    one-byte reads."""

    def __init__(self, console: bool = False):
        self.master_fd, self.slave_fd = os.openpty()
        _raw(self.slave_fd, vmin=1 if console else 0)  # one termios for both ends
        os.set_blocking(self.master_fd, False)
        self.slave_path = os.ttyname(self.slave_fd)

    def discard(self) -> None:
        """Drop the bytes queued in both directions (written by one end, not yet read by
        the other): a new process on the slave starts from a quiet line."""
        termios.tcflush(self.slave_fd, termios.TCIOFLUSH)

    def close(self) -> None:
        for fd in (self.master_fd, self.slave_fd):
            if fd >= 0:
                try:
                    os.close(fd)
                except OSError:
                    pass
        self.master_fd = self.slave_fd = -1
