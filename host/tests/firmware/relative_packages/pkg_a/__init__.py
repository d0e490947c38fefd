from . import helper  # noqa: F401
from .helper import VALUE  # noqa: F401
