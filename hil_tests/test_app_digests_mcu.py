"""Every world of every app with MCU time on (docs/mcu-time.md): the link trace's digest
pinned per MicroPython version (``test_app_digests.py``'s MCU_DIGESTS tables; a file of its
own so that make test's workers run it beside the free digests, not after them)."""

import pytest
from test_app_digests import DIGESTS, MCU_DIGESTS, MCU_DIGESTS_BY_VERSION, _check_digest, mcu_cpu, mcu_seconds

from host.core import interpreter

pytestmark = pytest.mark.hil


@pytest.mark.parametrize("key", list(DIGESTS), ids=lambda k: f"{k[0]}-{k[1]}-s{k[2]}")
def test_a_run_with_mcu_time_gives_its_pinned_digest(make_rig, monkeypatch, key, hil_mpy_version):
    """Every world of every app (DIGESTS' runs) with MCU time on, on its family's CPU
    (:func:`mcu_cpu`), for :func:`mcu_seconds`: the digest pinned for this MicroPython version."""
    monkeypatch.setenv("MPYFIL_CPU", mcu_cpu(key[0]))
    version = interpreter.release(hil_mpy_version).version
    table = MCU_DIGESTS if version == interpreter.DEFAULT_VERSION else MCU_DIGESTS_BY_VERSION.get(version, {})
    if key not in table:
        pytest.fail(f"{key}: no digest with MCU time pinned for MicroPython {version} (MCU_DIGESTS_BY_VERSION)")
    _check_digest(make_rig, key, table[key], mcu_seconds(key))
