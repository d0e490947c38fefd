"""Delta debugging (Zeller and Hildebrandt's ddmin) over a list: the smallest sublist
found for which a test still fails, 1-minimal (removing any one item makes it pass).

The test takes a batch of candidates and says, for each, whether it fails: a round's
candidates (the chunks, then the complements) go out together, so they can run in
parallel; the first failing one in the round's order is taken, whatever finished first,
so the result does not depend on how many ran at once.
"""

from collections.abc import Callable, Sequence

BatchTest = Callable[[list[list]], list[bool]]


def chunks(items: Sequence, n: int) -> list[list]:
    """``items`` cut into ``n`` nearly equal consecutive parts (the first ones longer)."""
    size, extra = divmod(len(items), n)
    out, start = [], 0
    for i in range(n):
        end = start + size + (1 if i < extra else 0)
        out.append(list(items[start:end]))
        start = end
    return [c for c in out if c]


def ddmin(items: Sequence, fails: BatchTest) -> list:
    """The 1-minimal failing sublist of ``items`` (which must fail): empty when nothing
    is needed for the failure (tried first)."""
    items = list(items)
    if not items or fails([[]])[0]:
        return []
    n = 2
    while len(items) >= 2:
        parts = chunks(items, n)
        found = _first(parts, fails)
        if found is not None:
            items, n = found, 2
            continue
        complements = [[x for x in items if x not in part] for part in parts] if n > 2 else []
        found = _first(complements, fails)
        if found is not None:
            items, n = found, max(n - 1, 2)
            continue
        if n >= len(items):
            break
        n = min(2 * n, len(items))
    return items


def _first(candidates: list[list], fails: BatchTest) -> list | None:
    if not candidates:
        return None
    for candidate, failed in zip(candidates, fails(candidates)):
        if failed:
            return candidate
    return None
