"""The plan of an ``external`` part played on the plant's timeline (docs/external.md),
without a firmware: an I2C write that plans an interrupt line's fall, a pin's changes that
take the place of those planned from their first on, the program's sends laid out on the
line in the order of their instants, 10 bits a byte; a snapshot restored and played again
gives the same changes and asks the program nothing twice."""

import json
import sys

from sim_plant.buses import XFER
from sim_plant.catalogue.assembly import assemble

PROGRAM = """#!{python}
import json
import sys

with open("seen.log", "w") as seen:
    for text in sys.stdin:
        msg = json.loads(text)
        seen.write(text)
        seen.flush()
        answer = {{}}
        if msg["op"] == "reset":
            answer = {{"pins": [[1000, "irq", 0], [2000, "irq", 1], [3000, "irq", 0]],
                       "uart": [[5000, "AB"], [4000, [67]]], "until_us": 8000}}
        elif msg["op"] == "write" and msg["byte"] == 0x99:
            answer = {{"ack": True, "pins": [[msg["t_us"] + 100, "irq", 1]]}}
        elif msg["op"] == "write":
            answer = {{"ack": True}}
        elif msg["op"] == "more":
            answer = {{"pins": [[msg["t_us"] + 500, "irq", 0]], "until_us": None}}
        print(json.dumps(answer), flush=True)
"""


def plant_in(tmp_path):
    script = tmp_path / "dev.py"
    script.write_text(PROGRAM.format(python=sys.executable))
    script.chmod(0o755)
    part = {"kind": "external", "name": "dev", "command": "dev.py", "address": 0x42}
    part |= {"pins_out": [["irq", 1]], "uart": True, "baud": 10_000}
    return assemble({"body": "bench", "parts": [part]}, base=tmp_path)


def test_a_plan_from_reset_an_i2c_write_and_more_is_played_at_its_instants(tmp_path):
    plant = plant_in(tmp_path)
    try:
        assert plant.output("dev.irq") == 1 and not (tmp_path / "seen.log").exists()
        assert [tuple(c) for c in plant.advance_to(1500)] == [(1000, "dev.irq", 0)]
        status = plant.bus_transfer("i2c0", XFER, 0x42, 0, bytes([0x10, 0x99]))[0]
        assert status == 0 and plant.next_change_us() == 1600  # the write's plan: the line up at 1,600 µs
        snap = plant.snapshot()  # (the host's, before a speculative batch)
        changes = [tuple(c) for c in plant.advance_to(10_000)]
        assert changes == [
            (1600, "dev.irq", 1),  # (the write's change took the place of those from 1,600 on: 2,000 and 3,000)
            (5000, "dev.uart", b"C"),  # sent at 4,000, 1 ms a byte at 10,000 baud
            (6000, "dev.uart", b"A"),  # the send at 5,000 waits for the line
            (7000, "dev.uart", b"B"),
            (8500, "dev.irq", 0),  # more at 8,000
        ], changes
        plant.restore(snap)  # (rewound: played again, the program's more answered from the answer kept)
        assert [tuple(c) for c in plant.advance_to(10_000)] == changes
        assert plant.advance_to(20_000) == [] and plant.next_change_us() > 10**15
    finally:
        plant.close()
    ops = [json.loads(line)["op"] for line in (tmp_path / "seen.log").read_text().splitlines()]
    assert ops == ["reset", "start", "write", "write", "stop", "more"], ops
