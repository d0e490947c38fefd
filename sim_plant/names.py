"""How every unknown name is refused: the whole list of known names, and the nearest
ones (by spelling, and by the words of what each name describes: ``neopixel`` finds
``ws2812_strip``, whose description says "neopixel").

One helper for every field that takes a name (a part's or a body's kind, a pin, a bus,
a view, a board, a world, a signal), so that each message reads the same and none is cut
short: the list is given whole.
"""

import difflib
import re

WORD = re.compile(r"[a-z0-9]+")
MAX_NEAREST = 3


def nearest(word, choices, described: dict | None = None) -> list[str]:
    """The names of ``choices`` nearest ``word``: close in spelling, or (with ``described``:
    name -> its description or aliases) described by a word close to it; at most three."""
    choices = [str(c) for c in choices]
    if not isinstance(word, str) or not word:
        return []
    lower = word.lower()
    key = "".join(WORD.findall(lower))
    said, like = [], []  # described by the word itself; by a word close to it
    for name, text in (described or {}).items():
        words = set(WORD.findall(str(text).lower())) | set(WORD.findall(name.lower()))
        if key and key in words:
            said.append(name)
        elif key and difflib.get_close_matches(key, words, n=1, cutoff=0.85):
            like.append(name)
    spelt = difflib.get_close_matches(word, choices, n=MAX_NEAREST, cutoff=0.6)
    spelt += difflib.get_close_matches(lower, choices, n=MAX_NEAREST, cutoff=0.6) if lower != word else []
    found: list[str] = []
    for name in [*said, *spelt, *like]:
        if name not in found:
            found.append(name)
    return found[:MAX_NEAREST]


def unknown(word, choices, described: dict | None = None, what: str = "known") -> str:
    """``(known: a, b, c); did you mean 'x'?``: every name of ``choices``, and the nearest
    ones to ``word``, for a message that refuses it."""
    choices = [str(c) for c in choices]
    close = nearest(word, choices, described)
    hint = f"; did you mean {' or '.join(map(repr, close))}?" if close else ""
    return f"({what}: {', '.join(choices) or 'none'}){hint}"
