"""``teamenv league-match`` without the humanoid extra: one clean line naming the extra, for
the in-process server too (simulated by hiding rcsssmj / mujoco)."""

from __future__ import annotations

import sys

import pytest

from teamenv.cli import main
from teamenv.errors import MissingExtraError
from teamenv.league.cli import _humanoid_extra

ARGS = ["league-match", "chaser", "chaser", "--team-size", "1", "--seconds", "0.1",
        "--no-progress"]


@pytest.mark.parametrize("hidden", ["rcsssmj", "mujoco"])
def test_local_server_without_the_extra_is_one_line(monkeypatch, capsys, hidden):
    monkeypatch.setitem(sys.modules, hidden, None)  # import of it now fails
    assert main([*ARGS, "--server", "local"]) == 2
    out, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("teamenv: error: league-match --server local needs the "
                               "'humanoid' extra")
    assert "pip install -e '.[humanoid]'" in lines[0]
    assert "Traceback" not in err


def test_other_import_errors_are_not_blamed_on_the_extra():
    with pytest.raises(MissingExtraError, match="'humanoid' extra \\(brax is not installed"):
        with _humanoid_extra("x"):
            raise ModuleNotFoundError("No module named 'brax.io'", name="brax.io")
    with pytest.raises(ModuleNotFoundError, match="somethingelse"):
        with _humanoid_extra("x"):
            raise ModuleNotFoundError("No module named 'somethingelse'", name="somethingelse")
