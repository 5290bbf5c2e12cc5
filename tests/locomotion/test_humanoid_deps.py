"""The humanoid extra is optional: importing locomotion never needs it, and a missing one is named."""

from __future__ import annotations

import subprocess
import sys

import pytest

from locomotion.humanoid import EXTRA_HINT, require


def test_missing_extra_names_the_install_command() -> None:
    with pytest.raises(ImportError, match=r"pip install -e '\.\[humanoid\]'"):
        require("surely_not_an_installed_module_xyz")
    assert "pip install -e '.[humanoid]'" in EXTRA_HINT


def test_locomotion_imports_no_heavy_or_upper_packages() -> None:
    code = (
        "import sys, locomotion, locomotion.humanoid, locomotion.humanoid.measure; "
        "bad = [m for m in ('jax', 'brax', 'mujoco', 'teamenv', 'strategy', 'comms') if m in sys.modules]; "
        "print(','.join(bad))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == ""
