"""``mpy-fil mcp`` (docs/live.md, "Over MCP"), driven by the ``mcp`` SDK's own client over
stdio: a rig started from its rig file, run to a console line, looked at, poked, taken back
to a snapshot, plotted; the limits refuse what is past them, naming the option."""

import os
import sys
from pathlib import Path

import anyio
import pytest

mcp = pytest.importorskip("mcp")
from mcp.client.stdio import stdio_client  # noqa: E402

REPO = Path(__file__).resolve().parents[2]
PICO = str(REPO / "examples" / "pico_bot" / "rig.toml")
ENV_KEYS = ("MICROPYTHON", "MICROPYTHON_SETTRACE", "PYTHONPATH", "PYTHONPYCACHEPREFIX", "MPY_FIL_BUSY_POLL")


def server(*options: str):
    env = {k: os.environ[k] for k in ENV_KEYS if k in os.environ}
    env["PYTHONPATH"] = str(REPO)
    code = "import sys; from host.cli import main; sys.exit(main(sys.argv[1:]))"
    args = ["-c", code, "mcp", *options]
    return stdio_client(mcp.StdioServerParameters(command=sys.executable, args=args, env=env, cwd=str(REPO)))


async def session_calls(options: tuple, script):
    async with server(*options) as (read, write), mcp.ClientSession(read, write) as session:
        await session.initialize()
        return await script(session)


def answer(result):
    assert not result.is_error, f"expected the tool to answer, it failed: {result.content[0].text}"
    return result.structured_content


def failure(result) -> str:
    assert result.is_error, f"expected the tool to refuse, it answered {result.structured_content}"
    return result.content[0].text


def test_an_agent_runs_looks_pokes_and_goes_back_over_stdio():
    async def script(s):
        names = {tool.name for tool in (await s.list_tools()).tools}
        started = answer(await s.call_tool("start", {"rig": PICO, "seed": 1, "record": True}))
        rig = {"rig_id": started["rig_id"]}
        ran = answer(await s.call_tool("run_until", {**rig, "console": "press start"}))
        before = answer(await s.call_tool("pins", rig))
        value = answer(await s.call_tool("eval", {**rig, "expression": "LOOP_MS"}))
        snap = answer(await s.call_tool("snapshot", rig))
        pressed = answer(await s.call_tool("press", {**rig, "button": "start", "ms": 100}))
        go = answer(await s.call_tool("run_until", {**rig, "console": "go", "timeout_s": 1}))
        answer(await s.call_tool("set_control", {**rig, "part": "sonar", "control": "distance", "value": 10}))
        turned = answer(await s.call_tool("run_until", {**rig, "console": "turning", "timeout_s": 1}))
        truth = answer(await s.call_tool("truth", rig))
        budgets = answer(await s.call_tool("budgets", rig))
        too_long = failure(await s.call_tool("step", {**rig, "ms": 120_000}))
        second = failure(await s.call_tool("start", {"rig": PICO}))
        back = answer(await s.call_tool("restore", {**rig, "snapshot": snap["snapshot"]}))
        again = answer(await s.call_tool("eval", {**rig, "expression": "enc_l.count"}))
        images = await s.call_tool("plots", rig)
        return locals()

    got = anyio.run(session_calls, (), script)
    assert {"start", "run_until", "pins", "eval", "exec", "press", "inject", "restore", "plots"} <= got["names"]
    assert got["ran"]["t_us"] == 10_000 and "pico_bot: press start" in got["ran"]["console"]
    assert got["before"]["BUTTON"]["level"] == 1 and got["value"] == {"value": 50}
    assert got["pressed"]["t_us"] == 110_000 and "pico_bot: go" in got["pressed"]["console"] + got["go"]["console"]
    assert "obstacle at 10 cm" in got["turned"]["console"] and got["truth"]["contacts"] == []
    assert got["budgets"]["loop"]["misses"] == 0
    assert "at most 60 (--max-run-s)" in got["too_long"]
    assert "at most 1 (mpy-fil mcp --max-rigs)" in got["second"]
    assert got["back"] == {"t_us": 10_000} and got["again"] == {"value": 0}
    pngs = [c for c in got["images"].content if c.type == "image"]
    assert not got["images"].is_error and pngs and all(c.mime_type == "image/png" for c in pngs), got["images"]


def test_a_rig_out_of_wall_time_stops_and_says_which_limit(tmp_path):
    """In memory (the SDK's Client on the server object): the limits are the server's own."""
    from host.live.mcpserver import Limits, make_server

    srv, rigs = make_server(Limits(max_wall_s=0.3), tmp_path)

    async def script():
        async with mcp.Client(srv) as s:
            rig = {"rig_id": answer(await s.call_tool("start", {"rig": PICO}))["rig_id"]}
            spent = failure(await s.call_tool("run_until", {**rig, "t_s": 50}))
            after = failure(await s.call_tool("step", {**rig, "ms": 10}))
            wrong = failure(await s.call_tool("eval", {"rig_id": "rig9", "expression": "1"}))
            answer(await s.call_tool("stop", rig))
            return spent, after, wrong

    try:
        spent, after, wrong = anyio.run(script)
    finally:
        rigs.close()
    assert "WallLimit" in spent and "wall time given to this rig is spent" in spent
    assert "has spent its 0.3 wall s (--max-wall-s)" in after
    assert "no rig 'rig9' open (open: rig1)" in wrong
    assert not rigs.open
