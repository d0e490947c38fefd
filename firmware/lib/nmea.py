# NMEA 0183 sentences from a byte stream (a UART at 4800 baud): whole lines in,
# checksum checked (XOR of the characters between '$' and '*', two hex digits).
# A line longer than the standard's 82 characters is dropped; so is one with a
# missing or wrong checksum (counted in bad). Pure Python: CPython tests use it too.
try:
    from micropython import const
except ImportError:  # CPython

    def const(x):
        return x


MAX_LINE = const(82)  # NMEA 0183: at most 82 characters including $ and CR LF


class NmeaLines:
    def __init__(self):
        self._buf = bytearray()
        self._skip = False  # inside an over-long line: drop until its end
        self.bad = 0

    def feed(self, data):
        """Bytes in; the complete sentences they end, as bytes from '$' up to before
        '*', checksum verified."""
        out = []
        for b in data:
            if b == 10:  # LF ends a line
                if not self._skip and self._buf:
                    body = self._check(self._buf)
                    if body is None:
                        self.bad += 1
                    else:
                        out.append(body)
                self._buf = bytearray()
                self._skip = False
            elif b == 36:  # '$' starts a sentence, even after garbage
                self._buf = bytearray(b"$")
                self._skip = False
            elif not self._skip:
                if len(self._buf) >= MAX_LINE:
                    self._skip = True
                    self._buf = bytearray()
                    self.bad += 1
                elif self._buf:
                    self._buf.append(b)
        return out

    @staticmethod
    def _check(line):
        if line and line[-1] == 13:  # CR
            line = line[:-1]
        star = line.find(b"*")
        if line[:1] != b"$" or star < 0 or len(line) != star + 3:
            return None
        cs = 0
        for b in line[1:star]:
            cs ^= b
        try:
            if int(bytes(line[star + 1 :]), 16) != cs:
                return None
        except ValueError:
            return None
        return bytes(line[:star])


NO_ECHO = -1.0  # a valid sentence whose depth field is empty: the sounder heard nothing


def dpt_depth_m(sentence):
    """Depth of a '$--DPT,<m>,<offset>' sentence (any talker): metres, NO_ECHO for an
    empty field, None for another sentence type or an unreadable field."""
    if sentence[3:7] != b"DPT,":
        return None
    end = sentence.find(b",", 7)
    field = sentence[7:] if end < 0 else sentence[7:end]
    if not field:
        return NO_ECHO
    try:
        depth = float(field)
    except ValueError:
        return None
    return depth if depth >= 0.0 else None
