"""Every rig file our apps had in 0.1 (``[plant] kind = ...``, kept as they were in
``host/tests/data/rig01/``, from the commits that moved each app to a body and parts),
written in today's form by ``host/rig/config/migrate.py``, runs its firmware to the link trace
pinned for the app (``test_app_digests.py``): the first world of each app is run, and every
world's plant is the app's own, part for part and option for option."""

import hashlib

import pytest
import tomllib
from test_app_digests import APP_PATHS, DIGESTS, RUN_S, SECONDS, digest_before

from host.core.paths import REPO
from host.rig.config.apps import get_app
from host.rig.config.migrate import migrate_text
from host.rig.config.rigfile import rig_from_data

pytestmark = pytest.mark.hil

DATA = REPO / "host" / "tests" / "data" / "rig01"
OLD = {  # app -> its 0.1 rig file
    "rover": "rover/rig.toml",
    "pool_cleaner": "pool_cleaner/rig.toml",
    "pool_cleaner_adc": "pool_cleaner/rig-adc.toml",
    "vacuum": "vacuum/rig.toml",
    "duct": "duct/rig.toml",
    "lab_robot": "lab_robot/rig.toml",
    "lab_robot_canyon": "lab_robot/rig-canyon.toml",
    "pico_bot": "pico_bot/rig.toml",
}


def migrated(app: str, tmp_path):
    """The app's 0.1 rig file in today's form, as an App whose firmware is the app's."""
    text, _ = migrate_text((DATA / OLD[app]).read_text())
    path = tmp_path / f"{app}.migrated.toml"
    path.write_text(text)  # (kept beside the run's artefacts for a reader)
    ours = get_app(APP_PATHS.get(app, app))
    return rig_from_data(path, tomllib.loads(text), base=ours.rig_file.parent), ours


def test_every_app_of_ours_had_a_0_1_rig_file_here():
    apps = {key[0] for key in DIGESTS}
    assert apps == set(OLD), f"apps with pinned digests {sorted(apps)}, 0.1 rig files for {sorted(OLD)}"
    for name in OLD.values():
        assert 'kind = "' in (DATA / name).read_text().partition("[plant]")[2][:200], f"{name}: not 0.1's form"


@pytest.mark.parametrize("app", sorted(OLD))
def test_a_migrated_0_1_rig_builds_the_apps_plant_in_every_world(app, tmp_path):
    new, ours = migrated(app, tmp_path)
    assert new.name == ours.name and new.wiring == ours.wiring, (new.wiring, ours.wiring)
    assert list(new.worlds) == list(ours.worlds), (new.worlds, ours.worlds)
    for world in ours.worlds:
        assert new.worlds[world] == ours.worlds[world], f"{app} [worlds.{world}]: {new.worlds[world]}"
        mine, theirs = new.make_plant(**new.worlds[world]), ours.make_plant(**ours.worlds[world])
        assert mine.describe() == theirs.describe(), f"{app} in {world}: the plants differ"
        budgets = [(b.name, b.limit_text()) for b in new.make_budgets(mine)]
        assert budgets == [(b.name, b.limit_text()) for b in ours.make_budgets(theirs)], budgets


@pytest.mark.parametrize("key", [k for k in DIGESTS if k[1] == next(iter(get_app(APP_PATHS.get(k[0], k[0])).worlds))])
def test_a_migrated_0_1_rig_gives_the_pinned_link_trace(make_rig, key, tmp_path):
    app, world, seed = key
    new, _ = migrated(app, tmp_path)
    seconds = SECONDS.get(app, RUN_S)
    rig = make_rig(new, seed=seed, plant_options=dict(new.worlds[world]), trace=True)
    rig.run_for(seconds)
    rig.stop()
    trace = (rig.artefacts / "trace.jsonl").read_bytes()
    assert hashlib.sha256(trace).hexdigest() == rig.trace_digest
    got = digest_before(trace, app)
    assert got == DIGESTS[key], f"{app} migrated from 0.1, in {world}: link trace {got} ({rig.artefacts})"
