"""MicroPython's own tests through the harness (``make conformance``, docs/shim.md).

Upstream's ``tests/run-tests.py``, from the source the build fetched, runs a set of
test files twice: on the plain unix port, and in the loop (:mod:`.inloop`: each file is
a firmware's entry file, under the shim, against a bench of wires). A test that passes
on the plain port must pass in the loop, or be listed in ``known.toml`` with a reason
that holds on a real board.
"""
