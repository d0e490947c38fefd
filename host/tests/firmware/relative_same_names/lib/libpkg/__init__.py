from . import util  # noqa: F401
from .util import VALUE  # noqa: F401


def late():
    from . import util as mine

    return mine.VALUE
