from machine import Pin

from .webserver import Webserver

led = Pin(0, Pin.OUT)
webserver = Webserver.get_default_webserver()
