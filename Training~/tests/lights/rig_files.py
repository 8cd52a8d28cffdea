"""A rig file written and then edited as JSON, for the tests of what reading a bad rig says."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Callable

from lpnn.lights.rig import Rig, write_rig


def edited_rig(tmp_path: Path, rig: Rig, change: Callable[[dict[str, Any]], Any]) -> Path:
    """`rig` written to tmp_path/rig.json, its JSON document changed in place by `change`, written back."""
    path = write_rig(tmp_path / "rig.json", rig)
    document = json.loads(path.read_text())
    change(document)
    path.write_text(json.dumps(document))
    return path
