"""`lpnn`'s commands: every `lpnn/cli/*_cmd.py` is a top-level command, and `scene lights` is an action of `scene` only
(its module, cli/scene_lights.py, is not a *_cmd.py: it once also showed up as a stray `lpnn lights`)."""

from __future__ import annotations

import pytest

from lpnn.cli.main import main


def test_lights_is_an_action_of_scene_only(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit):
        main(["--help"])
    commands = capsys.readouterr().out
    assert "    scene " in commands and "    place " in commands
    assert "    lights " not in commands
    with pytest.raises(SystemExit) as done:
        main(["scene", "lights", "--help"])
    assert done.value.code == 0 and "--compare" in capsys.readouterr().out
