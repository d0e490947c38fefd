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
    # the duct robot as a differential body over parts: line for line the trace of its plant
    # class (7324cc9c..., 9b8d905e..., f0e0454a..., 4ebdcd72...) but for the header's plant
    # (PartsPlant, was DuctRobot) and its encoders' signals in their CFG lines (enc_l.out, was
    # enc_l); the worlds are the differential body's duct worlds now; docs/duct.md
    ("duct", (), 1): "5c2aa787f4a90135b6cdd55a8c639e8df61071d95e54eba03a5b9c7361e038a0",
    ("duct", (("world", "multi_branch_duct"),), 2): "fff557b0b23dc97989634d409b2d5a574b7155a4764612feb7e05cb09aac50ab",
    ("duct", (("world", "straight_duct"),), 3): "697688613f17340ce66cff2062134cba4fd4fcaa6a5f37ccae8fb88e2e1c9ed9",
    ("duct", (("world", "bench_duct"),), 1): "13d2468d2684452de9611836bdadfe4d97d10db216a075aa2f36f0e51f8ac6c2",
}


@pytest.mark.parametrize("key", list(DIGESTS), ids=lambda k: f"{k[0]}-{dict(k[1]).get('world', 'default')}-s{k[2]}")
def test_link_trace_digest_is_the_recorded_one(make_rig, key):
    app, options, seed = key
    rig = make_rig(app, seed=seed, plant_options=dict(options), trace=True)
    rig.run_for(SECONDS[app])
    assert rig.t_us >= SECONDS[app] * 1e6 and "Traceback" not in rig.console, rig.console[-800:]
    assert rig.trace_digest == DIGESTS[key], f"{app} {dict(options)} seed {seed}: the link trace changed"
