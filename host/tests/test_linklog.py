"""The link log's hot messages (OUT, WAIT, STATE) are formatted by hand for speed: the
same bytes as the JSON encoder writes for the other messages, whatever the numbers."""

import hashlib
import json

from hypothesis import given
from hypothesis import strategies as st

from host.artefacts.linklog import OUT_ATTRS, LinkLog
from host.link import frames as F

ints = st.integers(min_value=-(2**63), max_value=2**64)
encode = json.JSONEncoder(separators=(",", ":"), sort_keys=True).encode


class Lines(LinkLog):
    def __init__(self):
        super().__init__()
        self.written = []

    def _put(self, text: str, lines: int) -> None:
        super()._put(text, lines)
        self.written += text.splitlines(keepends=True)


def one_line(call) -> str:
    log = Lines()
    call(log)
    log.flush()
    assert len(log.written) == 1, f"expected one line, got {log.written}"
    return log.written[0]


@given(ints, ints, st.sampled_from([*OUT_ATTRS, 99]), ints | st.booleans())
def test_out_lines_are_what_the_encoder_writes(t, h, attr, value):
    want = encode({"t": t, "msg": "OUT", "handle": h, "attr": OUT_ATTRS.get(attr, attr), "value": value}) + "\n"
    assert one_line(lambda log: log.out(t, h, attr, value)) == want


@given(ints, ints, st.frozensets(st.integers(0, 65535)))
def test_wait_lines_are_what_the_encoder_writes(t, until, watch):
    want = encode({"t": t, "msg": "WAIT", "until": until, "watch": sorted(watch)}) + "\n"
    assert one_line(lambda log: log.wait(t, until, watch)) == want


change = st.one_of(
    st.tuples(ints, ints, st.integers(0, 8).filter(lambda k: k != F.CH_BYTES), ints, ints | st.text(max_size=4)),
    st.binary(max_size=8).map(lambda b: (5, 2, F.CH_BYTES, len(b), b)),
)


@given(ints, ints, ints, st.lists(change, max_size=6))
def test_state_lines_are_what_the_encoder_writes(t, base, horizon, changes):
    entries = [[ct, h, k, v, e.hex() if k == F.CH_BYTES else e] for ct, h, k, v, e in changes]
    want = encode({"t": t, "to": "fw", "msg": "STATE", "base": base, "horizon": horizon, "changes": entries}) + "\n"
    assert one_line(lambda log: log.state(t, base, horizon, changes)) == want


def test_the_digest_covers_the_hand_written_lines():
    a, b = LinkLog(), LinkLog()
    a.out(1, 2, F.OUT_LEVEL, 1)
    b.out(1, 2, F.OUT_LEVEL, 0)
    assert a.digest != b.digest and a.lines == b.lines == 1


def test_records_kept_until_the_state_are_written_in_order_whole_and_counted(tmp_path):
    log = LinkLog(tmp_path / "trace.jsonl")
    log.out(1, 2, F.OUT_LEVEL, 1)
    log.wait(1, 5, frozenset({2}))
    assert log.lines == 2 and (tmp_path / "trace.jsonl").read_text() == ""  # (kept until the STATE)
    log.state(5, 1, 9, [(5, 2, 0, 1, 0)])
    written = (tmp_path / "trace.jsonl").read_text().splitlines()
    assert [json.loads(line)["msg"] for line in written] == ["OUT", "WAIT", "STATE"]
    log.fault(6)
    digest = log.digest  # (writes what is kept)
    log.close()
    text = (tmp_path / "trace.jsonl").read_text()
    assert text.endswith('{"msg":"FAULT","t":6}\n') and log.lines == 4
    assert digest == hashlib.sha256(text.encode()).hexdigest()
