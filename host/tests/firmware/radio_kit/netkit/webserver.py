import network
import time

import usocket


class Webserver:
    _default = None

    @classmethod
    def get_default_webserver(cls):
        if cls._default is None:
            cls._default = Webserver()
        return cls._default

    def __init__(self):
        # (made at import, so that stop() before start() finds an interface)
        self.wlan = network.WLAN(network.STA_IF)
        self.ip = None
        self.dns = None
        self.http = None

    def connect_to_network(self, ssid, password, timeout_s=5):
        self.wlan = network.WLAN(network.STA_IF)
        self.wlan.active(True)
        self.wlan.connect(ssid, password)
        start = time.ticks_ms()
        seen = [(self.wlan.status(), 0)]  # each status and when it was first seen, in ms
        while not self.wlan.isconnected():
            waited = time.ticks_diff(time.ticks_ms(), start)
            if waited > timeout_s * 1000:
                self.wlan.disconnect()
                return False, seen
            if self.wlan.status() != seen[-1][0]:
                seen.append((self.wlan.status(), waited))
            time.sleep_ms(100)
        return True, seen

    def start_network(self, ssid="KIT_1", password="remote.kit"):
        self.wlan = network.WLAN(network.AP_IF)
        self.wlan.config(essid=ssid, password=password)
        self.wlan.active(True)
        self.ip = self.wlan.ifconfig()[0]

    def start_server(self):
        # a catch-all DNS on UDP 53 and HTTP on TCP 80, as a captive-portal server binds them
        self.dns = usocket.socket(usocket.AF_INET, usocket.SOCK_DGRAM)
        self.dns.setblocking(False)
        self.dns.setsockopt(usocket.SOL_SOCKET, usocket.SO_REUSEADDR, 1)
        self.dns.bind(usocket.getaddrinfo(self.ip, 53, 0, usocket.SOCK_DGRAM)[0][-1])
        self.http = usocket.socket()
        self.http.setsockopt(usocket.SOL_SOCKET, usocket.SO_REUSEADDR, 1)
        self.http.bind(("0.0.0.0", 80))
        self.http.listen(2)

    def stop_server(self):
        for s in (self.dns, self.http):
            if s is not None:
                s.close()
        if self.wlan.active():
            self.wlan.active(False)
