"""A chip served from outside the rig (docs/external.md): a small script answers the
firmware's I2C transfers in lockstep, stamped with virtual time; a program that answers
out of protocol, or not at all, stops the run naming it; the program ends with the rig."""

import textwrap
from pathlib import Path

import pytest

from host.live import LiveRig
from sim_plant.catalogue.external import ExternalError

RIG = """
name = "external_chip"

[board]
family = "esp32"

[board.pins]
SCL = 22
SDA = 21

[plant]
body = "bench"

[[plant.parts]]
kind = "external"
name = "chip"
command = "chip.py"
address = 0x42
timeout_s = 1.0

[wiring]
"""
MAIN = """
import time

from machine import I2C, Pin

i2c = I2C(0, scl=Pin(22), sda=Pin(21), freq=400000)
print("scan", i2c.scan())
print("id", i2c.readfrom_mem(0x42, 0x0F, 1)[0])
i2c.writeto_mem(0x42, 0x20, b"\\x07")
while True:
    time.sleep_ms(100)
    count = i2c.readfrom_mem(0x42, 0x20, 1)[0]
    print("count", count)
"""
CHIP = """#!/usr/bin/env python3
# A register chip served from outside: WHO_AM_I (0x0F) reads 0x68, 0x20 counts up at each
# read; every request's instant is kept in seen.log.
import json
import sys

regs = {0x0F: 0x68}
pointer, pointed = 0, False
with open("seen.log", "w") as seen:
    for line in sys.stdin:
        msg = json.loads(line)
        seen.write("%d %s\\n" % (msg["t_us"], msg["op"]))
        answer = {}
        if msg["op"] == "start":
            pointed = msg["read"]
        elif msg["op"] == "write":
            if not pointed:
                pointer, pointed = msg["byte"], True
            else:
                regs[pointer] = msg["byte"]
                pointer += 1
            answer = {"ack": True}
        elif msg["op"] == "read":
            answer = {"byte": regs.get(pointer, 0)}
            if pointer == 0x20:
                regs[0x20] = (regs[0x20] + 1) & 0xFF
            pointer += 1
        print(json.dumps(answer), flush=True)
"""


def project(tmp_path: Path, chip: str = CHIP) -> Path:
    (tmp_path / "rig.toml").write_text(RIG)
    (tmp_path / "main.py").write_text(textwrap.dedent(MAIN))
    script = tmp_path / "chip.py"
    script.write_text(chip)
    script.chmod(0o755)
    return tmp_path / "rig.toml"


def test_a_script_serves_a_chip_in_lockstep_and_sees_each_transfers_virtual_instant(tmp_path):
    with LiveRig.start(project(tmp_path)) as rig:
        rig.run_until(console=r"count 9\b", timeout_s=1)
        assert "scan [66]\nid 104\ncount 7\ncount 8\n" in rig.console(), rig.console()
        assert rig.eval("count") == 9 and 300_000 <= rig.t_us <= 310_000, rig.t_us
        reads = [tx for tx in rig.bus_log() if tx["register"] == 0x20 and tx["read"]]
        assert [tx["read"] for tx in reads] == ["07", "08", "09"]
        assert all(99_000 < b["t_us"] - a["t_us"] < 101_000 for a, b in zip(reads, reads[1:])), reads
    seen = (tmp_path / "seen.log").read_text().splitlines()  # (whole: the program ended with the rig)
    instants = sorted({int(line.split()[0]) for line in seen if line.endswith("read")})
    assert instants[-3:] == [tx["t_us"] for tx in reads], f"expected the reads' virtual instants, got {instants}"


def test_a_program_that_answers_out_of_protocol_stops_the_run_naming_it(tmp_path):
    rig_file = project(tmp_path, "#!/bin/sh\nwhile read line; do echo 'not json'; done\n")
    with LiveRig.start(rig_file) as rig:
        said = r"rig.toml: \[\[plant.parts\]\] #1 \(chip\): expected one JSON object a line from .*chip.py"
        with pytest.raises(ExternalError, match=said):
            rig.run_until(t_s=0.1)


def test_a_program_that_does_not_answer_stops_the_run_after_its_timeout(tmp_path):
    rig_file = project(tmp_path, "#!/bin/sh\necho $$ > pid\nexec sleep 30\n")
    with LiveRig.start(rig_file) as rig:
        with pytest.raises(ExternalError, match=r"gave no answer to .* within 1 wall s"):
            rig.run_until(t_s=0.1)
    pid = int((tmp_path / "pid").read_text())
    assert not Path(f"/proc/{pid}").exists(), f"expected the program (pid {pid}) killed as the rig stopped"
