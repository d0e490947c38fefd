# network: the board's radio, modelled as one with no network in range (docs/shim.md,
# "The radio: network and socket"). A board with a radio (_hilboards.radio: the ESP32s, the
# CYW43 boards: Pico W, Pico 2 W, the XRP controllers) has it, built in as on the board
# (extmod/modnetwork.c registers it non-extensible: a firmware's network.py does not take its
# name, host/shim/_hilconfine.py); elsewhere `import network` fails as on a board without one.
#
# What the firmware sees: WLAN(STA_IF) and WLAN(AP_IF), each one object as the port's static
# ones; active(), connect() that never connects (status() CONNECTING, then the port's "no AP
# found" NO_AP_US later in virtual time; isconnected() False), scan() [] after SCAN_US,
# ifconfig()/ipconfig()/config() as each port answers them (an active AP at 192.168.4.1, no
# station ever joins), network.hostname(), network.country(), network.ipconfig(). The
# constants as each port's C defines them: extmod/network_cyw43.c and extmod/modnetwork.c (the
# CYW43 boards, lib/cyw43-driver's values), ports/esp32/network_wlan.c and
# modnetwork_globals.h (ESP-IDF's values, per the IDF each MicroPython version is built with).
# Nothing here reaches the host's network.
import sys

import _hil
from _hilboards import radio

_board = sys.modules.get("sys", sys)
_RADIO = radio(getattr(_board, "platform", ""), getattr(getattr(_board, "implementation", None), "_machine", "") or "")
if _RADIO is None:
    raise ImportError("no module named 'network'")
_KIND, _HOSTNAME = _RADIO
_MPY = sys.implementation.version[:2]

# Not the chip's figures, estimates (docs/shim.md): a connect's scan of the 2.4 GHz channels
# for its network, then the port's "no AP found"; a scan() of them all.
NO_AP_US = 2_500_000
SCAN_US = 2_500_000

_hostname = _HOSTNAME
_country = "XX"  # extmod/modnetwork.c, mod_network_country_code
_ZEROS = ("0.0.0.0", "0.0.0.0", "0.0.0.0", "0.0.0.0")
_AP_UP = ("192.168.4.1", "255.255.255.0", "192.168.4.1")  # both ports' default soft AP


def _now():
    _hil.observe()
    return _hil.now()


def _wait(us):
    _hil.blocking()
    _hil.run_until(_hil.now() + us)


def country(*args):
    global _country
    if len(args) > 1:
        raise TypeError("function takes at most 1 positional arguments")
    if not args:
        return _country
    if not isinstance(args[0], str):
        raise TypeError("can't convert %s to str" % type(args[0]).__name__)
    if len(args[0]) != 2:
        raise ValueError
    _country = args[0]


def hostname(*args):
    global _hostname
    if len(args) > 1:
        raise TypeError("function takes at most 1 positional arguments")
    if not args:
        return _hostname
    if not isinstance(args[0], str):
        raise TypeError("can't convert %s to str" % type(args[0]).__name__)
    if len(args[0]) > 32:  # MICROPY_PY_NETWORK_HOSTNAME_MAX_LEN
        raise ValueError
    _hostname = args[0]


def _get_one(args, kwargs):
    if kwargs:
        if args:
            raise TypeError("can't specify pos and kw args")
        return None
    if len(args) != 1:
        raise TypeError("must query one param")
    return args[0]


def _valid_ip(text):
    parts = text.split(".") if isinstance(text, str) else ()
    if len(parts) != 4 or not all(p.isdigit() and int(p) < 256 for p in parts):
        raise ValueError("invalid arguments")
    return text


_dns = ["0.0.0.0"]  # lwIP's dns_getserver(0); the CYW43's STA sets 8.8.8.8 as it comes up


def ipconfig(*args, **kwargs):
    """network.ipconfig: extmod/network_lwip.c mod_network_ipconfig (rp2),
    ports/esp32/network_common.c esp_network_ipconfig."""
    key = _get_one(args, kwargs)
    if key is None:
        for k, v in kwargs.items():
            if k == "dns":
                _dns[0] = _valid_ip(v)
            elif k == "prefer" and _KIND == "cyw43":
                if v not in (4, 6):
                    raise ValueError("invalid prefer argument")
            else:
                raise ValueError("unexpected key")
        return None
    if key == "dns":
        return _dns[0]
    if key == "prefer" and _KIND == "cyw43":
        return 4
    raise ValueError("unexpected key")


def route():
    return []  # (MICROPY_PORT_NETWORK_INTERFACES: no NIC registers itself under lwIP)


class _Nic:
    # one interface's addresses, as its netif holds them
    def __init__(self, addresses, dhcp):
        self.addresses = addresses
        self.dhcp = dhcp

    def ifconfig(self, args):
        if not args:
            a = self.addresses
            return (a[0], a[1], a[2], _dns[0] if _KIND == "cyw43" else a[3])
        cfg = args[0]
        if isinstance(cfg, str):
            if cfg != "dhcp" or self is not _nics[0]:
                raise ValueError("invalid arguments")
            self.dhcp = True
            if _KIND == "cyw43":  # extmod/network_lwip.c: waits 10 s for DHCP's address
                _wait(10_000_000)
                raise OSError("timeout waiting for DHCP to get IP address")
            return None
        if not isinstance(cfg, (tuple, list)) or len(cfg) != 4:
            raise ValueError("tuple/list has wrong length")
        a = [_valid_ip(cfg[0]), cfg[1], _valid_ip(cfg[2]), _valid_ip(cfg[3])]
        if isinstance(a[1], int):  # (the ESP32 takes a prefix length)
            bits = (0xFFFFFFFF << (32 - a[1])) & 0xFFFFFFFF
            a[1] = ".".join(str(bits >> s & 255) for s in (24, 16, 8, 0))
        a[1] = _valid_ip(a[1])
        self.addresses = tuple(a)
        if _KIND == "cyw43":
            _dns[0] = a[3]
        self.dhcp = False
        return None

    def ipconfig(self, args, kwargs):
        key = _get_one(args, kwargs)
        a = self.addresses
        if key is None:
            for k, v in kwargs.items():
                if k == "dhcp4":
                    self.dhcp = bool(v)
                elif k == "addr4":
                    ip, _, prefix = v.partition("/") if isinstance(v, str) else (v[0], "", v[1])
                    if isinstance(prefix, str):
                        prefix = int(prefix) if prefix else 24
                    bits = (0xFFFFFFFF << (32 - prefix)) & 0xFFFFFFFF
                    mask = ".".join(str(bits >> s & 255) for s in (24, 16, 8, 0))
                    self.addresses = (_valid_ip(ip), mask, a[2], a[3])
                    self.dhcp = False
                elif k == "gw4":
                    self.addresses = (a[0], a[1], _valid_ip(v), a[3])
                else:
                    raise ValueError("unexpected key")
            return None
        if key == "addr4":
            return (a[0], a[1])
        if key == "gw4":
            return a[2]
        if key == "dhcp4":
            return self.dhcp
        if key == "has_dhcp4":
            return self.dhcp and a[0] != "0.0.0.0"
        raise ValueError("unexpected key")


STA_IF = 0  # MOD_NETWORK_STA_IF (extmod/modnetwork.h); the ESP32's WIFI_IF_STA
AP_IF = 1  # MOD_NETWORK_AP_IF; WIFI_IF_AP

if _KIND == "cyw43":
    # CYW43_LINK_* (lib/cyw43-driver/src/cyw43.h), as extmod/modnetwork.c names them
    STAT_IDLE = 0  # CYW43_LINK_DOWN
    STAT_CONNECTING = 1  # CYW43_LINK_JOIN
    STAT_WRONG_PASSWORD = -3  # CYW43_LINK_BADAUTH
    STAT_NO_AP_FOUND = -2  # CYW43_LINK_NONET
    STAT_CONNECT_FAIL = -1  # CYW43_LINK_FAIL
    STAT_GOT_IP = 3  # CYW43_LINK_UP
    _nics = [_Nic(_ZEROS, True), _Nic(_ZEROS, False)]
else:
    STAT_IDLE = 1000  # ports/esp32/modnetwork.h
    STAT_CONNECTING = 1001
    STAT_GOT_IP = 1010
    STAT_BEACON_TIMEOUT = 200  # ESP-IDF's wifi_err_reason_t (esp_wifi_types.h)
    STAT_NO_AP_FOUND = 201
    STAT_WRONG_PASSWORD = 202
    STAT_ASSOC_FAIL = 203
    STAT_CONNECT_FAIL = 203
    STAT_HANDSHAKE_TIMEOUT = 204
    STAT_NO_AP_FOUND_W_COMPATIBLE_SECURITY = 210
    STAT_NO_AP_FOUND_IN_AUTHMODE_THRESHOLD = 211
    STAT_NO_AP_FOUND_IN_RSSI_THRESHOLD = 212
    MODE_11B = 1  # WIFI_PROTOCOL_11B
    MODE_11G = 2
    MODE_11N = 4
    MODE_LR = 8
    AUTH_OPEN = 0  # wifi_auth_mode_t
    AUTH_WEP = 1
    AUTH_WPA_PSK = 2
    AUTH_WPA2_PSK = 3
    AUTH_WPA_WPA2_PSK = 4
    AUTH_WPA2_ENTERPRISE = 5
    AUTH_WPA3_PSK = 6
    AUTH_WPA2_WPA3_PSK = 7
    AUTH_WAPI_PSK = 8
    AUTH_OWE = 9
    AUTH_WPA3_ENT_192 = 10
    AUTH_WPA3_EXT_PSK = 11
    AUTH_WPA3_EXT_PSK_MIXED_MODE = 12
    # WIFI_AUTH_MAX: 13 with ESP-IDF 5.2 (MicroPython 1.25's), 16 with 5.4 (1.26's), 17 with 5.5 (1.27's)
    AUTH_MAX = 13 if _MPY < (1, 26) else 16 if _MPY < (1, 27) else 17
    # the STA's netif has no address until DHCP gives one; the AP's is static from the start
    _nics = [_Nic(_ZEROS, True), _Nic(_AP_UP + ("0.0.0.0",), False)]


_MAC = (b"\x28\xcd\xc1\x00\x00\x01", b"\x28\xcd\xc1\x00\x00\x02")  # (made up, in the vendor's OUI)
if _KIND == "esp32":
    _MAC = (b"\x24\x0a\xc4\x00\x00\x01", b"\x24\x0a\xc4\x00\x00\x02")


class _State:
    active = [False, False]
    joined_at = None  # virtual time of the last connect(), or None (none, or disconnected)
    sta_ssid = ""
    ap_ssid = "PICO0000" if _KIND == "cyw43" else "ESP_000002"  # rp2/main.c: "PICO" + the unique id's hex
    ap_key = "picoW123" if _KIND == "cyw43" else ""
    ap_security = 0x00400004 if _KIND == "cyw43" else 0  # CYW43_AUTH_WPA2_AES_PSK; the IDF's open AP
    ap_hidden = False
    channel = 3 if _KIND == "cyw43" else 1  # cyw43_ctrl.c ap_channel = 3; the IDF's AP channel 1
    pm = 0xA11142 if _KIND == "cyw43" else 1  # CYW43_DEFAULT_PM (PERFORMANCE); WIFI_PS_MIN_MODEM
    reconnects = -1
    protocol = 7  # 11B | 11G | 11N
    stopped = False  # (ESP32: a connect then disconnect(): STAT_IDLE)


def _no_ap_yet():
    """True while the last connect() still looks for its network, False once it has not
    found it; None: no connect() since the last disconnect()."""
    if _State.joined_at is None:
        return None
    return _now() - _State.joined_at < NO_AP_US


def _ssid_arg(value):
    if not isinstance(value, (str, bytes, bytearray)):
        raise TypeError("object with buffer protocol required")
    return value if isinstance(value, str) else bytes(value).decode()


class WLAN:
    IF_STA = 0
    IF_AP = 1
    if _KIND == "cyw43":
        SEC_OPEN = 0  # CYW43_AUTH_OPEN (lib/cyw43-driver/src/cyw43_ll.h)
        SEC_WPA_WPA2 = 0x00400006  # CYW43_AUTH_WPA2_MIXED_PSK
        SEC_WPA3 = 0x01000004  # CYW43_AUTH_WPA3_SAE_AES_PSK
        SEC_WPA2_WPA3 = 0x01400004  # CYW43_AUTH_WPA3_WPA2_AES_PSK
        PM_NONE = 0x10  # CYW43_PM_VALUE(CYW43_NO_POWERSAVE_MODE, 10, 0, 0, 0)
        PM_PERFORMANCE = 0xA11142  # CYW43_PM_VALUE(CYW43_PM2_POWERSAVE_MODE, 200, 1, 1, 10)
        PM_POWERSAVE = 0x11  # CYW43_PM_VALUE(CYW43_PM1_POWERSAVE_MODE, 10, 0, 0, 0)
    else:
        SEC_OPEN = 0
        SEC_WEP = 1
        SEC_WPA = 2
        SEC_WPA2 = 3
        SEC_WPA_WPA2 = 4
        SEC_WPA2_ENT = 5
        SEC_WPA3 = 6
        SEC_WPA2_WPA3 = 7
        SEC_WAPI = 8
        SEC_OWE = 9
        SEC_WPA3_ENT_192 = 10
        SEC_WPA3_EXT_PSK = 11
        SEC_WPA3_EXT_PSK_MIXED_MODE = 12
        if _MPY >= (1, 26):  # ESP-IDF 5.4 (1.26's)
            SEC_DPP = 13
            SEC_WPA3_ENT = 14
            SEC_WPA2_WPA3_ENT = 15
        if _MPY >= (1, 27):  # ESP-IDF 5.5 (1.27's and 1.28's)
            SEC_WPA_ENT = 16
            PROTOCOL_DEFAULT = 7
            PROTOCOL_LR = 8
        PM_NONE = 0  # WIFI_PS_NONE
        PM_PERFORMANCE = 1  # WIFI_PS_MIN_MODEM
        PM_POWERSAVE = 2  # WIFI_PS_MAX_MODEM

    _objects = [None, None]

    def __new__(cls, interface=0):
        if not isinstance(interface, int):
            raise TypeError("can't convert %s to int" % type(interface).__name__)
        if _KIND == "cyw43":
            itf = 0 if interface == STA_IF else 1  # network_cyw43_make_new: any other is the AP
        elif interface in (0, 1):
            itf = interface
        else:
            raise ValueError("invalid WLAN interface identifier")
        if cls._objects[itf] is None:
            obj = object.__new__(cls)
            obj._itf = itf
            cls._objects[itf] = obj
        return cls._objects[itf]

    def __init__(self, interface=0):
        pass

    def __repr__(self):
        if _KIND != "cyw43":
            return "<WLAN>"
        status = {0: "down", 1: "join", 3: "up", -2: "nonet", -3: "badauth"}.get(self._link(), "fail")
        return "<CYW43 %s %s %s>" % ("STA" if self._itf == 0 else "AP", status, _nics[self._itf].addresses[0])

    # -- the interface

    def active(self, *args):
        if len(args) > 1:
            raise TypeError("function takes at most 2 positional arguments")
        if args:
            on = bool(args[0])
            if on and not _State.active[self._itf]:
                if _KIND == "cyw43":  # the netif comes up with cyw43_lwip.c's defaults
                    if self._itf == 0:
                        _nics[0].addresses = ("0.0.0.0", "255.255.255.0", "192.168.0.1", "0.0.0.0")
                        _dns[0] = "8.8.8.8"
                    else:
                        _nics[1].addresses = _AP_UP + ("0.0.0.0",)
            if not on and self._itf == 0 and (_KIND == "esp32" or _MPY >= (1, 28)):
                _State.joined_at = None  # (1.28's network_cyw43_active leaves; the ESP32's STA stops)
            _State.active[self._itf] = on
            if _KIND == "cyw43":
                return None
        return _State.active[self._itf]

    def deinit(self):
        _State.active[0] = _State.active[1] = False
        _State.joined_at = None

    def _link(self):
        # cyw43_tcpip_link_status
        if self._itf == 1:
            return 3 if _State.active[1] else 0
        searching = _no_ap_yet()
        return 0 if searching is None else 1 if searching else -2

    def connect(self, ssid=None, key=None, *, bssid=None, auth=-1, security=-1, channel=0):
        if _KIND == "cyw43":
            if ssid is None:
                raise TypeError("'ssid' argument required")
            _ssid_arg(ssid)
            if key is not None:
                _ssid_arg(key)
            if bssid is not None and len(bssid) != 6:
                raise ValueError
            if not _State.active[0]:  # cyw43_wifi_join: -CYW43_EPERM
                raise OSError(1)
        else:
            if not (_State.active[0] or _State.active[1]):
                raise OSError("Wifi Not Started")
            if not _State.active[0]:
                raise OSError("Wifi Invalid Mode")
            if bssid is not None and len(bssid) != 6:
                raise ValueError
        if ssid is not None:
            _State.sta_ssid = _ssid_arg(ssid)
        _State.joined_at = _now()
        _State.stopped = False

    def disconnect(self):
        if _State.joined_at is not None:
            _State.stopped = True
        _State.joined_at = None

    def isconnected(self):
        return False  # (no network to join; no station joins the AP)

    def status(self, *args):
        if len(args) > 1:
            raise TypeError("function takes at most 2 positional arguments")
        if not args:
            if _KIND == "cyw43":
                return self._link()
            if self._itf == 1:
                return None
            searching = _no_ap_yet()
            if searching is None:
                return STAT_IDLE
            return STAT_CONNECTING if searching else STAT_NO_AP_FOUND
        param = args[0]
        if param == "rssi":
            self._require(0)
            if _KIND == "esp32":
                raise OSError("Wifi Not Connected")
            return 0  # (cyw43_wifi_get_rssi of no network)
        if param == "stations":
            self._require(1)
            return []
        raise ValueError("unknown status param")

    def _require(self, itf):
        if self._itf != itf:
            text = "STA required" if itf == 0 else "AP required"
            raise (ValueError if _KIND == "cyw43" else OSError)(text)

    def scan(self, *args, **kwargs):
        if _KIND == "cyw43":
            if args:
                raise TypeError("function takes 1 positional arguments but %d were given" % (len(args) + 1))
            for k in kwargs:
                if k not in ("passive", "ssid", "essid", "bssid"):
                    raise TypeError("unexpected keyword argument '%s'" % k)
            if not (_State.active[0] or _State.active[1]):  # cyw43_wifi_scan: -CYW43_EPERM
                raise OSError(1)
        else:
            if args or kwargs:
                raise TypeError("function takes 1 positional arguments")
            if not _State.active[0]:
                raise OSError("STA must be active")
        _wait(SCAN_US)
        return []

    def ifconfig(self, *args):
        if len(args) > 1:
            raise TypeError("function takes at most 2 positional arguments")
        return _nics[self._itf].ifconfig(args)

    def ipconfig(self, *args, **kwargs):
        return _nics[self._itf].ipconfig(args, kwargs)

    def config(self, *args, **kwargs):
        if _KIND == "cyw43":
            return self._config_cyw43(args, kwargs)
        return self._config_esp32(args, kwargs)

    def _config_cyw43(self, args, kwargs):
        # extmod/network_cyw43.c, network_cyw43_config
        if not kwargs:
            if len(args) != 1:
                raise TypeError("must query one param")
            key = args[0]
            if key in ("ssid", "essid"):
                return _State.ap_ssid if self._itf == 1 else ""
            if key == "mac":
                return _MAC[self._itf]
            if key in _CYW43_GET:
                return _CYW43_GET[key]()
            if key == "txpower":
                raise ValueError("config param 'txpower' is not in the loop (docs/shim.md, the radio)")
            raise ValueError("unknown config param")
        if args:
            raise TypeError("can't specify pos and kw args")
        for k, v in kwargs.items():
            if k in _CYW43_SET:
                _CYW43_SET[k](v)
            elif k not in ("antenna", "monitor", "trace", "txpower"):
                raise ValueError("unknown config param")

    def _config_esp32(self, args, kwargs):
        # ports/esp32/network_wlan.c, network_wlan_config: an interface's key checked after
        if args and kwargs:
            raise TypeError("either pos or kw args are allowed")
        if kwargs:
            for k, v in kwargs.items():
                if k == "mac":
                    if len(v) != 6:
                        raise ValueError("invalid buffer length")
                    continue
                if k in ("max_clients", "txpower"):
                    continue
                if k not in _ESP32_SET:
                    raise ValueError("unknown config param")
                need, setter = _ESP32_SET[k]
                setter(v)
                if need >= 0:
                    self._require(need)
            return None
        if len(args) != 1:
            raise TypeError("can query only one param")
        key = args[0]
        if key == "mac":
            return _MAC[self._itf]
        if key in ("ssid", "essid"):
            return _State.sta_ssid if self._itf == 0 else _State.ap_ssid
        if key in ("ifname", "max_clients", "txpower"):
            raise ValueError("config param '%s' is not in the loop (docs/shim.md, the radio)" % key)
        if key not in _ESP32_GET:
            raise ValueError("unknown config param")
        need, getter = _ESP32_GET[key]
        if need >= 0:
            self._require(need)
        return getter()


def _setter(name, convert):
    def set_(value):
        setattr(_State, name, convert(value))

    return set_


def _getter(name):
    return lambda: getattr(_State, name)


# config() keys: the CYW43's (network_cyw43_config) and the ESP32's (network_wlan_config,
# with the interface each requires: 0 the STA, 1 the AP, -1 either)
_CYW43_GET = {
    "antenna": lambda: 0,
    "channel": _getter("channel"),
    "security": _getter("ap_security"),
    "pm": _getter("pm"),
    "hostname": lambda: _hostname,
}
_CYW43_SET = {
    "ssid": _setter("ap_ssid", _ssid_arg),
    "essid": _setter("ap_ssid", _ssid_arg),
    "key": _setter("ap_key", _ssid_arg),
    "password": _setter("ap_key", _ssid_arg),
    "security": _setter("ap_security", int),
    "channel": _setter("channel", int),
    "pm": _setter("pm", int),
    "hostname": hostname,
}
_ESP32_GET = {
    "hidden": (1, _getter("ap_hidden")),
    "security": (1, _getter("ap_security")),
    "authmode": (1, _getter("ap_security")),
    "channel": (-1, _getter("channel")),
    "hostname": (0, lambda: _hostname),
    "dhcp_hostname": (0, lambda: _hostname),
    "reconnects": (0, _getter("reconnects")),
    "protocol": (-1, _getter("protocol")),
    "pm": (-1, _getter("pm")),
}
_ESP32_SET = {
    "ssid": (1, _setter("ap_ssid", lambda v: _ssid_arg(v)[:32])),
    "essid": (1, _setter("ap_ssid", lambda v: _ssid_arg(v)[:32])),
    "hidden": (1, _setter("ap_hidden", bool)),
    "security": (1, _setter("ap_security", int)),
    "authmode": (1, _setter("ap_security", int)),
    "key": (1, _setter("ap_key", lambda v: _ssid_arg(v)[:63])),
    "password": (1, _setter("ap_key", lambda v: _ssid_arg(v)[:63])),
    "channel": (-1, _setter("channel", int)),
    "hostname": (-1, hostname),
    "dhcp_hostname": (-1, hostname),
    "reconnects": (0, _setter("reconnects", int)),
    "protocol": (-1, _setter("protocol", int)),
    "pm": (-1, _setter("pm", int)),
}
