"""The radio of a board that has one, with no network in range (docs/shim.md, "The radio:
network and socket"): a kit library in XRPLib's style (firmware/radio_kit: its defaults
build a web server that takes a WLAN at import, then joins, opens an AP and binds its
sockets as a captive portal does) runs unchanged on the XRP kits' rigs (CYW43: the rp2
port's values) and on an ESP32 rig (ESP-IDF's), and stops at `import network` on a plain
Pico, as on each board. The firmware never reaches the host's network."""

import shutil
import socket

import pytest

from host.core.paths import REPO
from host.tests.conftest import FIRMWARE, results
from host.tests.test_shim_board import bench
from host.tests.test_version_behaviour import VERSIONS, on_version  # noqa: F401  (a fixture)

pytestmark = pytest.mark.hil

KIT = FIRMWARE / "radio_kit"

PLAIN = """
[firmware]
entry = "main.py"

[board]
family = "{family}"

[board.pins]
LED = 2

[plant]
body = "bench"

[wiring]
"""


def _run(make_rig, tmp_path, rig_text: str, main: str | None = None, seconds: float = 20.0) -> tuple[dict, str]:
    fw = tmp_path / "fw"
    shutil.copytree(KIT, fw)
    if main is not None:
        (fw / "main.py").write_text(main)
    (fw / "rig.toml").write_text(rig_text)
    rig = make_rig(str(fw / "rig.toml"), allow_exit=True)
    rig.run_for(seconds)
    rig.stop()
    where = f"console:\n{rig.console}\nartefacts: {rig.artefacts}"
    return results(rig.console), where


def _kit_rig(kit: str) -> str:
    return (REPO / "host" / "kits" / kit / "rig.toml").read_text()


@pytest.mark.parametrize("kit", ["xrp", "xrp_beta"])
def test_a_kit_librarys_web_server_imports_and_finds_no_network_on_the_xrp(make_rig, tmp_path, kit):
    r, where = _run(make_rig, tmp_path, _kit_rig(kit))
    assert r.get("done") is True, f"expected the firmware to finish; {where}"
    assert r["hostname"] == "XRP", f"expected the board's MICROPY_PY_NETWORK_HOSTNAME_DEFAULT; {where}"
    assert r["sta_same"] and r["socket_is_usocket"], f"expected one STA object, socket the board's; {where}"
    assert r["sta_active_before"] is False, where
    # CYW43_LINK_JOIN, then CYW43_LINK_NONET 2.5 s of virtual time after connect() (within a poll)
    assert r["stat"] == (0, 1, -2, 3), f"expected the CYW43 link constants; {where}"
    (first, _), (second, at_ms) = r["statuses"]
    assert (first, second) == (1, -2) and 2500 <= at_ms <= 2600, f"expected JOIN then NONET at 2.5 s; {where}"
    assert r["connected"] is False and r["isconnected"] is False, where
    assert r["status_after_disconnect"] == 0, f"expected CYW43_LINK_DOWN after disconnect(); {where}"
    assert r["scan"] == [] and r["scan_ms"] == 2500, f"expected an empty scan taking 2.5 s; {where}"
    assert r["sta_ifconfig"] == ("0.0.0.0", "255.255.255.0", "192.168.0.1", "8.8.8.8"), where
    assert r["if_sta"] == (0, 1), where
    assert r["ap_active"] is True and r["ap_essid"] == "KIT_1" and r["ap_isconnected"] is False, where
    assert r["ap_ifconfig"] == ("192.168.4.1", "255.255.255.0", "192.168.4.1", "8.8.8.8"), where
    assert r["accept_nonblocking"] == ("OSError", 11), f"expected EAGAIN: no client; {where}"
    assert r["accept_timeout"] == ("OSError", 110) and r["accept_ms"] == 500, f"expected ETIMEDOUT at 0.5 s; {where}"
    assert r["dns_recv"] == ("OSError", 11), where
    assert r["dns_sendto_station"] == ("ok", 1), f"expected a datagram into the AP's subnet to go out; {where}"
    assert r["connect_internet"] == ("OSError", 113), f"expected EHOSTUNREACH: no route; {where}"
    assert r["getaddrinfo_name"] == ("OSError", -2), f"expected lwIP's -2: no DNS answers; {where}"
    assert r["connect_station"] == ("OSError", 115), f"expected EINPROGRESS into the AP's subnet; {where}"
    assert r["poll_waiting"] == [] and r["poll_ms"] == 200, f"expected no client, no answer: 200 ms; {where}"
    assert r["poll_udp_writable"] == [(True, 4)], f"expected the UDP socket alone writable; {where}"
    assert r["rebind_80"] == ("OSError", 98), f"expected EADDRINUSE (the other without SO_REUSEADDR); {where}"
    assert r["ap_active_after"] is False, where


def test_the_same_library_on_an_esp32_gets_esp_idfs_values(make_rig, tmp_path):
    r, where = _run(make_rig, tmp_path, PLAIN.format(family="esp32"))
    assert r.get("done") is True, f"expected the firmware to finish; {where}"
    assert r["hostname"] == "mpy-esp32", where
    assert r["stat"] == (1000, 1001, 201, 1010), f"expected ports/esp32's STAT_* values; {where}"
    (first, _), (second, at_ms) = r["statuses"]
    assert (first, second) == (1001, 201) and 2500 <= at_ms <= 2600, f"expected CONNECTING then 201; {where}"
    assert r["status_after_disconnect"] == 1000, f"expected STAT_IDLE after disconnect(); {where}"
    assert r["sta_ifconfig"] == ("0.0.0.0",) * 4, where
    assert r["ap_ifconfig"] == ("192.168.4.1", "255.255.255.0", "192.168.4.1", "0.0.0.0"), where
    assert r["accept_timeout"] == ("OSError", 116), f"expected newlib's ETIMEDOUT; {where}"
    assert r["connect_internet"] == ("OSError", 118), f"expected newlib's EHOSTUNREACH; {where}"
    assert r["getaddrinfo_name"] == ("OSError", -202), where
    assert r["connect_station"] == ("OSError", 119), f"expected newlib's EINPROGRESS; {where}"
    assert r["poll_waiting"] == [] and r["poll_udp_writable"] == [(True, 4)], where
    assert r["rebind_80"] == ("OSError", 112), where


def test_a_plain_pico_has_no_network(make_rig, tmp_path):
    r, where = _run(make_rig, tmp_path, PLAIN.format(family="rpi_pico"), seconds=1.0)
    assert r.get("import_error") == "no module named 'network'", f"expected the board's ImportError; {where}"


OWN_FILES = """
import sys
import network
print("R network", getattr(network, "MINE", False))
import socket, usocket
print("R socket", repr((getattr(socket, "MINE", False), getattr(usocket, "MINE", False))))
sys.exit()
"""


def test_a_firmwares_network_py_loses_to_the_built_in_and_its_socket_py_wins(make_rig, tmp_path):
    """network is a non-extensible built-in (extmod/modnetwork.c), socket an extensible one
    (extmod/modlwip.c): a file of the firmware's takes socket's name, not usocket's."""
    fw_extra = {"network.py": "MINE = True\n", "socket.py": "MINE = True\n"}
    fw = tmp_path / "fw"
    shutil.copytree(KIT, fw)
    for name, text in fw_extra.items():
        (fw / name).write_text(text)
    (fw / "main.py").write_text(OWN_FILES)
    (fw / "rig.toml").write_text(_kit_rig("xrp"))
    rig = make_rig(str(fw / "rig.toml"), allow_exit=True)
    rig.run_for(1.0)
    rig.stop()
    r = results(rig.console)
    where = f"console:\n{rig.console}\nartefacts: {rig.artefacts}"
    assert r.get("network") is False, f"expected the board's network, not the file; {where}"
    assert r.get("socket") == (True, False), f"expected socket.py to win, usocket the board's; {where}"


HOST_NET = """
import sys
import socket
def attempt(what, f):
    try:
        print("R", what, repr(("ok", f())))
    except OSError as e:
        print("R", what, repr(("OSError", e.args[0])))
s = socket.socket()
attempt("connect_host", lambda: s.connect(socket.getaddrinfo("127.0.0.1", {port})[0][-1]))
l = socket.socket()
attempt("bind", lambda: l.bind(("0.0.0.0", {free})))
attempt("listen", lambda: l.listen(1))
print("R listening True")
import time
time.sleep_ms(300)
sys.exit()
"""


def test_the_boards_sockets_never_reach_the_hosts_network(make_rig, tmp_path):
    listener = socket.socket()
    listener.bind(("127.0.0.1", 0))
    listener.listen(1)
    listener.settimeout(0)
    port = listener.getsockname()[1]
    probe = socket.socket()
    probe.bind(("127.0.0.1", 0))
    free = probe.getsockname()[1]
    probe.close()
    try:
        fw = tmp_path / "fw"
        shutil.copytree(KIT, fw)
        (fw / "main.py").write_text(HOST_NET.format(port=port, free=free))
        (fw / "rig.toml").write_text(_kit_rig("xrp"))
        rig = make_rig(str(fw / "rig.toml"), allow_exit=True)
        rig.expect(r"R listening True\n")
        # the firmware "listens" on port `free`: the host's own port stays free
        taken = socket.socket()
        try:
            taken.bind(("0.0.0.0", free))
            host_port_free = True
        except OSError:
            host_port_free = False
        finally:
            taken.close()
        rig.run_for(1.0)
        rig.stop()
        try:
            conn, _ = listener.accept()
            conn.close()
            reached = True
        except BlockingIOError:
            reached = False
    finally:
        listener.close()
    r = results(rig.console)
    where = f"console:\n{rig.console}\nartefacts: {rig.artefacts}"
    assert r["connect_host"] == ("OSError", 113) and not reached, f"expected EHOSTUNREACH, no host connection; {where}"
    assert r["bind"] == ("ok", None) and r["listen"] == ("ok", None), where
    assert host_port_free, f"expected the firmware's bind to leave the host's port {free} alone; {where}"


@pytest.mark.parametrize("version", VERSIONS)
def test_the_esp32s_names_follow_each_versions_esp_idf(on_version, version):  # noqa: F811  (the fixture)
    """ports/esp32/network_wlan.c and modnetwork_globals.h, built with ESP-IDF 5.2 (1.25),
    5.4 (1.26: SEC_DPP, SEC_WPA3_ENT), 5.5 (1.27 and 1.28: SEC_WPA_ENT, PROTOCOL_DEFAULT);
    AUTH_MAX is the IDF's WIFI_AUTH_MAX; MSG_PEEK and MSG_DONTWAIT from 1.26
    (ports/esp32/modsocket.c, lwIP's 0x01 and 0x08)."""
    rig, r = on_version(version, bench("esp32_bench"), "ver_radio", 0.1)
    v = tuple(int(x) for x in version.split("."))
    sec = [] if v < (1, 26) else ["SEC_DPP", "SEC_WPA3_ENT"] if v < (1, 27) else None
    if sec is None:
        sec = ["PROTOCOL_DEFAULT", "SEC_DPP", "SEC_WPA3_ENT", "SEC_WPA_ENT"]
    expected = {"auth_max": {(1, 25): 13, (1, 26): 16}.get(v, 17), "sec": sec}
    expected["msg"] = [None, None] if v < (1, 26) else [1, 8]
    got = {k: r.get(k) for k in expected}
    assert got == expected, f"MicroPython {version} on an ESP32: got {got}, expected {expected} ({rig.artefacts})"
