# Buffers as the ports take them (docs/shim.md, "Buffers"). A board's C takes a buffer with
# mp_get_buffer_raise (py/obj.c): anything with the buffer protocol (bytes, bytearray, str,
# array of any typecode, memoryview and its slices), as its raw bytes in the machine's byte
# order (little-endian, as on an ESP32 or RP2040); anything else raises
# TypeError("object with buffer protocol required"). A buffer to fill must be writable
# (MP_BUFFER_WRITE): bytes, str and a memoryview of either are refused with that TypeError
# (py/objstr.c mp_obj_str_get_buffer, py/objarray.c array_get_buffer).
#
# rbuf(obj) gives the bytes a C function reads; wbuf(obj) a bytearray over obj's own bytes
# (obj itself for a bytearray), so that filling it fills an array('h') byte by byte as the
# C's memcpy does. bytes and bytearray, the common case, pass through untouched.
import struct

from uctypes import addressof, bytearray_at

_BYTEARRAY = 1  # BYTEARRAY_TYPECODE (py/binary.h)
_RW = 0x80  # MP_OBJ_ARRAY_TYPECODE_FLAG_RW (py/objarray.h): the memoryview may be written
# mp_obj_array_t (py/objarray.h) is its type pointer, then the typecode in the low byte of
# the next word: read there from a memoryview the firmware's object is seen through.
_TYPECODE_AT = struct.calcsize("P")
_NO_BUFFER = "object with buffer protocol required"  # (py/obj.c, mp_get_buffer_raise)


def typecode(view):
    """A memoryview's typecode as its C sees it: 'B' for bytes and str, 1 for a bytearray,
    the array's letter for an array, with _RW set when the memory may be written."""
    return bytearray_at(id(view) + _TYPECODE_AT, 1)[0]


def itemsize(code):
    code &= 0x7F
    return 1 if code == _BYTEARRAY else struct.calcsize(chr(code))


def rbuf(obj):
    """mp_get_buffer_raise(obj, &bufinfo, MP_BUFFER_READ): obj's bytes."""
    t = type(obj)
    if t is bytes or t is bytearray:
        return obj
    return bytes(memoryview(obj))  # (memoryview raises the port's TypeError for a non-buffer)


def wbuf(obj):
    """mp_get_buffer_raise(obj, &bufinfo, MP_BUFFER_WRITE): a bytearray over obj's bytes;
    assign to it a slice no longer than it is (fill does)."""
    if type(obj) is bytearray:
        return obj
    view = memoryview(obj)
    code = typecode(view)
    if not code & _RW:
        raise TypeError(_NO_BUFFER)
    return bytearray_at(addressof(view), len(view) * itemsize(code))


def fill(view, data):
    """The first len(data) bytes of a wbuf view set to data (no more than the view holds)."""
    n = len(data)
    if n > len(view):
        n = len(view)
        data = data[:n]
    view[:n] = data
    return n
