from . import util  # noqa: F401
from .util import VALUE  # noqa: F401


def late():
    from . import util as mine

    return mine.VALUE


from . import sub  # noqa: E402, F401
from .sub import Y  # noqa: E402, F401
