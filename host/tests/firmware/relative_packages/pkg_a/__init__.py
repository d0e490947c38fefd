from . import helper
from .helper import VALUE
