from ..util import VALUE

LEAF = VALUE + "/leaf"
