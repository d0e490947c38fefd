from .. import util as up
from . import util as own
from .leaf import LEAF  # noqa: F401

UP = up.VALUE
OWN = own.VALUE
Y = "p1.sub.Y"
