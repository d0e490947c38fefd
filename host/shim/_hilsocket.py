# socket (and usocket) on a board with a radio (docs/shim.md, "The radio: network and
# socket"): the board's lwIP sockets (extmod/modlwip.c on a CYW43 board, ports/esp32/
# modsocket.c on an ESP32), on a radio with no network in range and no station on its AP.
# _hilconfine puts this module in sys.modules as socket and usocket on such a board (the
# unix port's socket, the host's network, is taken away on every board: no call here
# reaches it). What a board does with no one to talk to:
# - socket(), setsockopt(), setblocking(), settimeout(), bind() (a port bound twice without
#   SO_REUSEADDR: EADDRINUSE), listen() (TCP only: EOPNOTSUPP), close() (then EBADF);
# - accept(), recv(), recvfrom(): nothing ever comes. Non-blocking: EAGAIN; with a timeout:
#   ETIMEDOUT once it has passed in virtual time; blocking: waits for ever in virtual time
#   (IRQs and Timers run), as a board with no client waits; select.poll never finds one
#   readable, nor a connecting TCP socket writable (ioctl, as lwIP's);
# - connect(): no route (no interface up whose subnet holds the address): EHOSTUNREACH at
#   once; into the soft AP's subnet (192.168.4.0/24, the AP active): no one answers the SYN,
#   so EINPROGRESS non-blocking, ETIMEDOUT after a timeout, or a wait for ever;
# - sendto(): into the AP's subnet or a broadcast with an interface up, the datagram goes
#   out and no one hears it (its length back); elsewhere EHOSTUNREACH; send() on a TCP
#   socket never connected: ENOTCONN;
# - getaddrinfo(): a numeric IPv4 address as lwIP gives it back; a name: no DNS server
#   answers (the CYW43 boards' OSError(-2), lwIP's; the ESP32's OSError(-202), EAI_FAIL).
# Errors carry each port's errno: MicroPython's own numbers on rp2 (py/mperrno.h, Linux's),
# newlib's on an ESP32 (its lwIP's errno: EHOSTUNREACH 118, ETIMEDOUT 116, ...).
import sys

import _hil
from _hilboards import radio

_board = sys.modules.get("sys", sys)
_RADIO = radio(getattr(_board, "platform", ""), getattr(getattr(_board, "implementation", None), "_machine", "") or "")
_ESP32 = _RADIO is not None and _RADIO[0] == "esp32"
_MPY = sys.implementation.version[:2]

AF_INET = 2
AF_INET6 = 10
SOCK_STREAM = 1
SOCK_DGRAM = 2
SOCK_RAW = 3
IPPROTO_IP = 0
IPPROTO_TCP = 6
if _ESP32:  # lwip/sockets.h (ESP-IDF)
    IPPROTO_UDP = 17
    SOL_SOCKET = 0xFFF
    SO_REUSEADDR = 0x0004
    SO_BROADCAST = 0x0020
    SO_BINDTODEVICE = 0x100B
    IP_ADD_MEMBERSHIP = 3
    TCP_NODELAY = 0x01
    _E = {"EAGAIN": 11, "EBADF": 9, "EINVAL": 22, "EADDRINUSE": 112, "ENOTCONN": 128, "ETIMEDOUT": 116}
    _E.update({"EHOSTUNREACH": 118, "EINPROGRESS": 119, "EOPNOTSUPP": 95, "EALREADY": 120})
    _NO_NAME = -202  # EAI_FAIL, as ports/esp32/modsocket.c raises it
    if _MPY >= (1, 26):
        MSG_PEEK = 0x01
        MSG_DONTWAIT = 0x08
else:  # extmod/modlwip.c
    SOL_SOCKET = 1
    SO_REUSEADDR = 0x04  # SOF_REUSEADDR
    SO_BROADCAST = 0x20  # SOF_BROADCAST
    IP_ADD_MEMBERSHIP = 0x400
    IP_DROP_MEMBERSHIP = 0x401
    TCP_NODELAY = 0x40  # TF_NODELAY
    _E = {"EAGAIN": 11, "EBADF": 9, "EINVAL": 22, "EADDRINUSE": 98, "ENOTCONN": 107, "ETIMEDOUT": 110}
    _E.update({"EHOSTUNREACH": 113, "EINPROGRESS": 115, "EOPNOTSUPP": 95, "EALREADY": 114})
    _NO_NAME = -2  # lwIP's DNS callback with no address (modlwip.c, lwip_getaddrinfo)
    if _MPY >= (1, 26):
        MSG_PEEK = 0x01
        MSG_DONTWAIT = 0x02


def _error(name):
    return OSError(_E[name])


def _radio_state():
    """(AP active, any interface active) of the shim's network module (none imported: the
    radio has never been brought up)."""
    net = sys.modules.get("network")
    state = getattr(net, "_State", None)
    if state is None:
        return False, False
    return state.active[1], state.active[0] or state.active[1]


def _ipv4(text):
    parts = text.split(".")
    if len(parts) != 4 or not all(p.isdigit() and int(p) < 256 for p in parts):
        return None
    return tuple(int(p) for p in parts)


def _address(addr):
    if not isinstance(addr, tuple) or len(addr) < 2:
        raise TypeError("object '%s' isn't a tuple or list" % type(addr).__name__)
    host, port = addr[0], addr[1]
    if not isinstance(port, int):
        raise TypeError("can't convert %s to int" % type(port).__name__)
    if host == "":
        return (0, 0, 0, 0), port
    ip = _ipv4(host) if isinstance(host, str) else None
    if ip is None:  # (a name: the port resolves it first, with no DNS to answer)
        getaddrinfo(host, port)
    return ip, port


def _routed(ip):
    """Whether an interface that is up reaches ip: the soft AP's subnet while the AP is up,
    a broadcast while any interface is (the STA never has an address)."""
    ap, up = _radio_state()
    if ip == (255, 255, 255, 255):
        return up
    return ap and ip[:3] == (192, 168, 4)


_bound = []  # (socket, type, port, SO_REUSEADDR) of each socket bound and not closed


def _wait_forever_or(timeout_s, name):
    """Nothing ever arrives: raise EAGAIN at once (non-blocking), ``name`` once the timeout
    has passed in virtual time, or wait for ever (a board with no client)."""
    if timeout_s == 0:
        raise _error("EAGAIN")
    _hil.blocking()
    if timeout_s is None:
        while True:
            _hil.run_until(_hil.FOREVER_US)
    _hil.run_until(_hil.now() + int(timeout_s * 1_000_000))
    raise _error(name)


class socket:
    def __init__(self, af=AF_INET, type=SOCK_STREAM, proto=0, *args):
        for v in (af, type, proto):
            if not isinstance(v, int):
                raise TypeError("can't convert %s to int" % v.__class__.__name__)
        if type not in (SOCK_STREAM, SOCK_DGRAM, SOCK_RAW):
            raise OSError(_E["EINVAL"])
        self._type = type
        self._timeout = None
        self._closed = False
        self._port = None
        self._listening = False
        self._connecting = False
        self._reuse = False

    def __repr__(self):
        return "<socket>"

    def _open(self):
        if self._closed:
            raise _error("EBADF")

    def close(self):
        if not self._closed and self._port is not None:
            _bound[:] = [b for b in _bound if b[0] is not self]
        self._closed = True

    def __del__(self):
        self.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def setsockopt(self, level, option, value):
        self._open()
        if option == SO_REUSEADDR:
            self._reuse = bool(value)

    def setblocking(self, flag):
        self._timeout = None if flag else 0

    def settimeout(self, value):
        self._timeout = None if value is None else value

    def bind(self, addr):
        self._open()
        _ip, port = _address(addr)
        for _other, kind, used, reuse in _bound:  # lwIP's tcp_bind, udp_bind: both must allow it
            if kind == self._type and used == port and port and not (reuse and self._reuse):
                raise _error("EADDRINUSE")
        _bound.append((self, self._type, port, self._reuse))
        self._port = port

    def listen(self, backlog=0):
        self._open()
        if self._type != SOCK_STREAM:
            raise _error("EOPNOTSUPP")
        self._listening = True

    def accept(self):
        self._open()
        if self._type != SOCK_STREAM:
            raise _error("EOPNOTSUPP")
        if not self._listening:
            raise _error("EINVAL")
        _wait_forever_or(self._timeout, "ETIMEDOUT")

    def connect(self, addr):
        self._open()
        ip, _port = _address(addr)
        if self._type != SOCK_STREAM:
            return None  # (a UDP socket's connect only sets its peer)
        if not _routed(ip):
            raise _error("EHOSTUNREACH")
        if self._connecting:
            raise _error("EALREADY")
        if self._timeout == 0:
            self._connecting = True
            raise _error("EINPROGRESS")
        _wait_forever_or(self._timeout, "ETIMEDOUT")

    def send(self, data, *flags):
        self._open()
        if self._type == SOCK_STREAM:
            raise _error("ENOTCONN")
        raise _error("EHOSTUNREACH")  # (no peer connected: lwIP's udp_send)

    sendall = send
    write = send

    def sendto(self, data, addr):
        self._open()
        ip, _port = _address(addr)
        if self._type == SOCK_STREAM:
            raise _error("ENOTCONN")
        if not _routed(ip):
            raise _error("EHOSTUNREACH")
        return len(data)  # (out over the air; no one there)

    def recv(self, bufsize, flags=0):
        self._open()
        if self._type == SOCK_STREAM and not self._listening:
            raise _error("ENOTCONN")
        dontwait = flags & globals().get("MSG_DONTWAIT", 0)
        _wait_forever_or(0 if dontwait else self._timeout, "ETIMEDOUT")

    def recvfrom(self, bufsize, flags=0):
        return self.recv(bufsize, flags)

    def read(self, size=-1):
        return self.recv(size)

    def readinto(self, buf, nbytes=-1):
        return self.recv(len(buf))

    def readline(self):
        return self.recv(1)

    def makefile(self, mode="rb", buffering=0):
        return self

    def ioctl(self, request, arg):
        # extmod/modlwip.c, lwip_socket_ioctl, as select.poll asks it (MP_STREAM_POLL, 3):
        # nothing is ever readable; a UDP socket is writable, a TCP one unless it connects;
        # one never connected hangs up (POLLHUP), a closed one is invalid (POLLNVAL)
        if request == 4:  # MP_STREAM_CLOSE
            self.close()
            return 0
        if request != 3:
            return -_E["EINVAL"]
        if self._closed:
            return 0x20
        ready = 0
        if arg & 0x0004 and (self._type != SOCK_STREAM or not self._connecting):
            ready |= 0x0004
        if self._type == SOCK_STREAM and not (self._listening or self._connecting):
            ready |= 0x0010
        return ready


def getaddrinfo(host, port, af=0, type=0, proto=0, flags=0):
    if not isinstance(port, int):
        raise TypeError("can't convert %s to int" % port.__class__.__name__)
    ip = _ipv4(host) if isinstance(host, str) else None
    if ip is None:
        raise OSError(_NO_NAME)
    if _ESP32:
        return [(AF_INET, type or SOCK_STREAM, proto, "", (host, port))]
    return [(AF_INET, SOCK_STREAM, 0, "", (host, port))]
