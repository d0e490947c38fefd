"""The link-trace digest of each app at a fixed seed, for a few virtual seconds, against
the value recorded before its plant became a rig file over catalogue parts: the same
firmware on the same robot sends and receives the same bytes at the same virtual times.
A digest that must change is explained in the commit that changes it and in the app's
doc page (``docs/<app>.md``)."""

import pytest

pytestmark = pytest.mark.hil

SECONDS = {"pool_cleaner": 60.0, "pool_cleaner_adc": 60.0, "duct": 8.0}
DIGESTS = {
    # (app, plant options, seed): SHA-256 of the link trace after SECONDS[app]. The trace's
    # header names the firmware folder relative to the repository (the same in every
    # checkout); recorded before that with the absolute folder of the checkout they were taken
    # in, these are the same traces with only that path made relative.
    # the pool cleaner as a tracked body over parts: its trace is line for line the one of
    # its plant class (fcd5869d..., aa745c7c...) but for the header's plant (PartsPlant, was
    # PoolCleaner) and its bumpers' signals in the two CFG lines (bumper_front.out, was
    # bumper_front: a part's signals are <name>.<signal>); docs/pool_cleaner.md
    ("pool_cleaner", (), 1): "4577ad759d11cc8e51f2deac1839bde231fce0316c4925ef3c82283f49064524",
    ("pool_cleaner_adc", (), 1): "12f2dc532fd9e6af36e07bf8ebc3044def2626230cb6285ed1127e92d3628fd0",
    # the duct robot as a differential body over parts: line for line the trace of its plant
    # class (7324cc9c..., 9b8d905e..., f0e0454a..., 4ebdcd72...) but for the header's plant
    # (PartsPlant, was DuctRobot) and its encoders' signals in their CFG lines (enc_l.out, was
    # enc_l); the worlds are the differential body's duct worlds now; docs/duct.md
    ("duct", (), 1): "66c62f1749ab403f6e1e2c60512362575c2f446399d96a24688272257dffe7d4",
    ("duct", (("world", "multi_branch_duct"),), 2): "b63877eb9871f2d36a6457ae948edbe4569fecfcf6a05e0ec2c687c513673210",
    ("duct", (("world", "straight_duct"),), 3): "658618a90b2173a52da94b906e2c1c7be8996f6ee1062a3e5dff71bf69fe6c0c",
    ("duct", (("world", "bench_duct"),), 1): "d5a8fd61e903de2fbe7c740495ba333aa1972554515763ba199726eb9ef4c459",
}


@pytest.mark.parametrize("key", list(DIGESTS), ids=lambda k: f"{k[0]}-{dict(k[1]).get('world', 'default')}-s{k[2]}")
def test_link_trace_digest_is_the_recorded_one(make_rig, key):
    app, options, seed = key
    rig = make_rig(app, seed=seed, plant_options=dict(options), trace=True)
    rig.run_for(SECONDS[app])
    assert rig.t_us >= SECONDS[app] * 1e6 and "Traceback" not in rig.console, rig.console[-800:]
    assert rig.trace_digest == DIGESTS[key], f"{app} {dict(options)} seed {seed}: the link trace changed"
