from . import util  # noqa: F401
from .util import VALUE  # noqa: F401


def late():
    from . import util as mine

    return mine.VALUE


import asyncio  # noqa: E402

LAZY = asyncio.wait_for  # (asyncio's __getattr__ imports .funcs: asyncio's, not this package's)
