"""NMEA 0183 sentences from UART bytes: checksums, lines split across reads, DPT depths."""

import pytest
from nmea import NO_ECHO, NmeaLines, dpt_depth_m


def test_depth_of_a_valid_dpt_sentence():
    lines = NmeaLines()
    assert lines.feed(b"$SDDPT,7.5,0.0*55\r\n") == [b"$SDDPT,7.5,0.0"]
    assert dpt_depth_m(b"$SDDPT,7.5,0.0") == 7.5


def test_a_sentence_split_across_reads_is_joined():
    lines = NmeaLines()
    assert lines.feed(b"$SDDPT,1") == []
    assert lines.feed(b"2.3,0.0*6") == []
    out = lines.feed(b"7\r\n$SDD")
    assert [dpt_depth_m(s) for s in out] == [12.3]


def test_a_wrong_or_missing_checksum_is_dropped_and_counted():
    lines = NmeaLines()
    assert lines.feed(b"$SDDPT,7.5,0.0*56\r\n$SDDPT,7.5,0.0\r\n$SDDPT,7.5,0.0*5G\r\n") == []
    assert lines.bad == 3


def test_garbage_before_a_dollar_and_overlong_lines_are_skipped():
    lines = NmeaLines()
    out = lines.feed(b"\x00\xff$" + b"9" * 100 + b"\r\n" + b"xx$SDDPT,3.1,0.0*55\r\n")
    assert [dpt_depth_m(s) for s in out] == [3.1] and lines.bad == 1


def test_empty_depth_field_is_no_echo_and_other_sentences_are_none():
    assert dpt_depth_m(b"$SDDPT,,0.0") == NO_ECHO
    assert dpt_depth_m(b"$SDDBT,24.6,f,7.5,M,4.1,F") is None
    assert dpt_depth_m(b"$SDDPT,x,0.0") is None


@pytest.mark.parametrize("sentence", [b"$SDDPT,,*57\r\n", b"$SDDBT,24.6,f,7.5,M,4.1,F*31\r\n"])
def test_checksums_from_the_seed_notes_are_accepted(sentence):
    assert NmeaLines().feed(sentence) == [sentence[:-5]]


def test_every_sentence_the_plants_sounder_sends_parses_back():
    """The plant's $SDDPT generator and the firmware's parser agree (one byte at a time)."""
    from sim_plant.physics.echo_sounder import dpt_sentence

    lines = NmeaLines()
    depths = [None, 0.1, 2.9, 7.5, 13.7, 19.9, 20.0, 150.0]
    stream = b"".join(dpt_sentence(d) for d in depths)
    got = [dpt_depth_m(s) for b in stream for s in lines.feed(bytes([b]))]
    assert got == [NO_ECHO if d is None else d for d in depths] and lines.bad == 0
