from . import util  # noqa: F401
from .util import VALUE  # noqa: F401


def late():
    from . import util as mine

    return mine.VALUE


import p1  # noqa: E402

OTHER = p1.late()  # (p1's function, called while p3 is being imported: p1's util)
