# The firmware of host/tests/test_network.py: a kit library's defaults imported as its
# users begin, then what its web server does on a radio with no network in range.
import sys
import time

try:
    from netkit.defaults import *  # noqa: F403  (as a kit's users begin)
    from netkit.defaults import webserver
except ImportError as e:
    print("R import_error", repr(str(e)))
    sys.exit()

import network
import select
import socket

import usocket


def say(name, value):
    print("R", name, repr(value))


def err(f):
    try:
        return ("ok", f())
    except OSError as e:
        return ("OSError", e.args[0])


say("hostname", network.hostname())
say("sta_same", network.WLAN(network.STA_IF) is webserver.wlan)
say("sta_active_before", webserver.wlan.active())
say("socket_is_usocket", socket is usocket)
ok, seen = webserver.connect_to_network("home", "secret", timeout_s=5)
say("connected", ok)
say("statuses", seen)
say("stat", (network.STAT_IDLE, network.STAT_CONNECTING, network.STAT_NO_AP_FOUND, network.STAT_GOT_IP))
say("status_after_disconnect", webserver.wlan.status())
say("isconnected", webserver.wlan.isconnected())
t0 = time.ticks_ms()
say("scan", webserver.wlan.scan())
say("scan_ms", time.ticks_diff(time.ticks_ms(), t0))
say("sta_ifconfig", webserver.wlan.ifconfig())
say("if_sta", (network.WLAN.IF_STA, network.WLAN.IF_AP))
webserver.start_network()
say("ap_active", webserver.wlan.active())
say("ap_ifconfig", webserver.wlan.ifconfig())
say("ap_essid", webserver.wlan.config("essid"))
say("ap_isconnected", webserver.wlan.isconnected())
webserver.start_server()
say("accept_nonblocking", err(lambda: (webserver.http.setblocking(False), webserver.http.accept())))
webserver.http.settimeout(0.5)
t0 = time.ticks_ms()
say("accept_timeout", err(webserver.http.accept))
say("accept_ms", time.ticks_diff(time.ticks_ms(), t0))
say("dns_recv", err(lambda: webserver.dns.recvfrom(256)))
say("dns_sendto_station", err(lambda: webserver.dns.sendto(b"x", ("192.168.4.2", 5353))))
out = socket.socket()
say("connect_internet", err(lambda: out.connect(("8.8.8.8", 80))))
say("getaddrinfo_name", err(lambda: socket.getaddrinfo("example.com", 80)))
station = socket.socket()
station.setblocking(False)
say("connect_station", err(lambda: station.connect(("192.168.4.2", 80))))
poller = select.poll()
poller.register(webserver.http, select.POLLIN)
poller.register(station, select.POLLOUT)
t0 = time.ticks_ms()
say("poll_waiting", [e for _, e in poller.poll(200)])
say("poll_ms", time.ticks_diff(time.ticks_ms(), t0))
poller.register(webserver.dns, select.POLLOUT)
say("poll_udp_writable", [(s is webserver.dns, e) for s, e in poller.poll(200)])
say("rebind_80", err(lambda: socket.socket().bind(("0.0.0.0", 80))))
webserver.stop_server()
say("ap_active_after", webserver.wlan.active())
say("done", True)
