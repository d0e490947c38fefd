"""The link-trace digest of each app at a fixed seed, for a few virtual seconds, against
the value recorded before its plant became a rig file over catalogue parts: the same
firmware on the same robot sends and receives the same bytes at the same virtual times.
A digest that must change is explained in the commit that changes it and in the app's
doc page (``docs/<app>.md``)."""

import pytest

pytestmark = pytest.mark.hil

SECONDS = {"pool_cleaner": 60.0, "pool_cleaner_adc": 60.0, "duct": 8.0}
DIGESTS = {
    # (app, plant options, seed): SHA-256 of the link trace after SECONDS[app]
    # the pool cleaner as a tracked body over parts: its trace is line for line the one of
    # its plant class (fcd5869d..., aa745c7c...) but for the header's plant (PartsPlant, was
    # PoolCleaner) and its bumpers' signals in the two CFG lines (bumper_front.out, was
    # bumper_front: a part's signals are <name>.<signal>); docs/pool_cleaner.md
    ("pool_cleaner", (), 1): "3570ed039613942cb3b85aabc4e53f4b648a4c84fc1b05d61b2b8aa1b8affb4d",
    ("pool_cleaner_adc", (), 1): "25c3cbec77382981f508ec26c51387a581c518f8c85f6e4b997979c81e62609d",
    ("duct", (), 1): "7324cc9c97f460346567dcc6ed3df8c4513ee3ef42e34ffbfba61842781e2891",
    ("duct", (("world", "multi_branch"),), 2): "9b8d905e8b9a3645dfc1dc1a9540d39cc620a45bd9ebb4eb6abb3730166741f2",
    ("duct", (("world", "straight_1m"),), 3): "f0e0454ab605dfaca8bf14b7f532c03efd816161f76d91239b14508eea1f7b23",
    ("duct", (("world", "bench"),), 1): "4ebdcd72877972b18a4c21963426dcefd12fcb2c61fe8620d9b9b97f08065fb6",
}


@pytest.mark.parametrize("key", list(DIGESTS), ids=lambda k: f"{k[0]}-{dict(k[1]).get('world', 'default')}-s{k[2]}")
def test_link_trace_digest_is_the_recorded_one(make_rig, key):
    app, options, seed = key
    rig = make_rig(app, seed=seed, plant_options=dict(options), trace=True)
    rig.run_for(SECONDS[app])
    assert rig.t_us >= SECONDS[app] * 1e6 and "Traceback" not in rig.console, rig.console[-800:]
    assert rig.trace_digest == DIGESTS[key], f"{app} {dict(options)} seed {seed}: the link trace changed"
