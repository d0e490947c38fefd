# PIO reads answered ahead (docs/shim.md, "PIO reads answered ahead"; docs/protocol.md,
# PIO_AHEAD and PIO_DONE): their payloads' layouts, for both ends (the shim's rp2.py and
# host/rig/pio_ahead.py). Apart from _hilframe so that a firmware without rp2 loads none of it.
import struct

PIO_AHEAD_FMT = "<B"  # entries, then each PIO_AHEAD_ENTRY_FMT, the bytes written, the bytes read
PIO_AHEAD_ENTRY_FMT = "<QBHBBBQHB"  # t_us, op, address, n_read, status, count, horizon_us, bytes written, sm
PIO_AHEAD_GOT_FMT = "<H"  # (after the bytes written) bytes read
PIO_DONE_FMT = "<QBB"  # t_us, state machine, the PIO_AHEAD's entry (its index)


def pack_pio_ahead(entries):
    """entries: [(t_us, op, address, n_read, data, status, count, horizon_us, got, sm)], the
    frames the firmware's reads make next (on the state machine ``sm``) and their replies, in
    the order it makes them."""
    out = [struct.pack(PIO_AHEAD_FMT, len(entries))]
    for t_us, op, address, n_read, data, status, count, horizon_us, got, sm in entries:
        fixed = (t_us, op, address, n_read, status, count, horizon_us, len(data), sm)
        out.append(struct.pack(PIO_AHEAD_ENTRY_FMT, *fixed))
        out.append(bytes(data))
        out.append(struct.pack(PIO_AHEAD_GOT_FMT, len(got)))
        out.append(bytes(got))
    return b"".join(out)


def unpack_pio_ahead(p):
    """[(t_us, op, address, n_read, data, status, count, horizon_us, got, sm)]"""
    if type(p) is not bytes:  # (slices of bytes are bytes: none made twice below)
        p = bytes(p)
    (n,) = struct.unpack_from(PIO_AHEAD_FMT, p, 0)
    off = _HEAD_SIZE
    unpack_from = struct.unpack_from
    out = []
    for _ in range(n):
        t_us, op, address, n_read, status, count, horizon_us, n_data, sm = unpack_from(PIO_AHEAD_ENTRY_FMT, p, off)
        off += _ENTRY_SIZE
        data = p[off : off + n_data] if n_data else b""
        off += n_data
        n_got = p[off] | p[off + 1] << 8  # (PIO_AHEAD_GOT_FMT, "<H", without its tuple)
        off += _GOT_SIZE
        out.append((t_us, op, address, n_read, data, status, count, horizon_us, p[off : off + n_got], sm))
        off += n_got
    return out


_HEAD_SIZE = struct.calcsize(PIO_AHEAD_FMT)
_ENTRY_SIZE = struct.calcsize(PIO_AHEAD_ENTRY_FMT)
_GOT_SIZE = struct.calcsize(PIO_AHEAD_GOT_FMT)


def pack_pio_done(t_us, sm_id, entry):
    return struct.pack(PIO_DONE_FMT, t_us, sm_id, entry)


def unpack_pio_done(p):
    return struct.unpack_from(PIO_DONE_FMT, p, 0)
