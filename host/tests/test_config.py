"""Bad scenario or configuration input is rejected with a message naming the field."""

import pytest

from host.core.errors import ConfigError
from host.rig import Rig, RigSpec


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"app": "no-such-app"}, "app:"),
        ({"board": "no_such_board"}, "board:"),
        ({"mode": "fast"}, "mode:"),
        ({"watchdog_s": 0}, "watchdog_s:"),
        ({"main_dir": "/nonexistent"}, "main_dir:"),
    ],
)
def test_bad_rig_settings_name_the_field(kwargs, field):
    with pytest.raises(ConfigError, match=field):
        Rig(RigSpec(**kwargs))
