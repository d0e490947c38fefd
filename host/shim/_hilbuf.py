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
# mp_obj_array_t (py/objarray.h) is its type pointer, then the typecode in the low byte of
# the next word, MP_OBJ_ARRAY_TYPECODE_FLAG_RW (0x80) set when it may be written.
_TYPECODE_AT = struct.calcsize("P")
_NO_BUFFER = "object with buffer protocol required"  # (py/obj.c, mp_get_buffer_raise)
_checked = []


def typecode(view):
    """A memoryview's typecode as its C sees it: 0x42 ('B') for bytes and str, 1 for a
    bytearray, the array's letter for an array (StateMachine.put and get go by it)."""
    if not _checked:  # (read where py/objarray.h puts it: checked once on known objects)
        from array import array

        for obj, code in ((b"", 0x42), (bytearray(), _BYTEARRAY), (array("h"), 0x68), (array("I"), 0x49)):
            if bytearray_at(id(memoryview(obj)) + _TYPECODE_AT, 1)[0] & 0x7F != code:
                raise RuntimeError("this interpreter's memoryview is not laid out as py/objarray.h's (1.25)")
        _checked.append(True)
    return bytearray_at(id(view) + _TYPECODE_AT, 1)[0] & 0x7F


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
    try:
        view[0:0] = view[0:0]  # (a view of bytes or str refuses it: py/objarray.c, array_subscr)
    except TypeError:
        raise TypeError(_NO_BUFFER) from None
    n = len(view)
    return bytearray_at(addressof(view), n and n * len(bytes(view[:1])))


def fill(view, data):
    """The first len(data) bytes of a wbuf view set to data (no more than the view holds)."""
    n = len(data)
    if n > len(view):
        n = len(view)
        data = data[:n]
    view[:n] = data
    return n
