# A firmware that resets at once at every boot (a wrong config check, say).
import machine

machine.reset()
