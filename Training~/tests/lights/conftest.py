"""Fixtures of the light-rig tests. The BSP writer of the importer tests is shared, not copied."""

from __future__ import annotations

import sys
from pathlib import Path

# tests/scenes/synthetic_bsp.py: the independent IBSP writer (pytest puts a test folder on the path
# only once it collects it, and this folder's tests also run alone)
sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "scenes"))
