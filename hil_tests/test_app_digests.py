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
    ("pool_cleaner", (), 1): "fcd5869d4a010b71f4cb99531031cddac48db2c61855088b1826b4c74e0fbcde",
    ("pool_cleaner_adc", (), 1): "aa745c7c73d3ffbe85fd01ed57fa733dd68d024571dd9a095edeef3bbadc056d",
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
