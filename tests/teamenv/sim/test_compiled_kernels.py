"""The numba kernels (observation rows, heard slots, `simspark` hearing) are compiled lazily,
on first use and not at ``import teamenv``, and give bit for bit what the NumPy code they
replaced gave: env runs hash as recorded before the kernels existed."""

import subprocess
import sys

import pytest

from tests.golden import env_run_hash

# Recorded with the NumPy versions of StatePerception.observe, Simulation._deliver's slot
# filling and Channel._hear_by_capacity (the commit before the kernels).
RECORDED = {
    (11, 60, 5, "simspark"): "7cc7bce52d7f46fa4138bf0c980dc24bfad20f3e9acea187b08716a12e8c55f3",
    (3, 80, 7, "mj7v7"): "ec0f98137b9f92b9283cdff816b5aeae48c6d7999edf58365b1a9d81ec4946b7",
}


def test_numba_is_imported_on_first_use_not_with_teamenv():
    code = (
        "import sys, teamenv\n"
        "env = teamenv.parallel_env(team_size=2)\n"
        "print('numba' in sys.modules)\n"
        "env.reset(seed=0)\n"
        "print('numba' in sys.modules)\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout.split()
    assert out == ["False", "True"]


@pytest.mark.parametrize(("team_size", "steps", "seed", "field"), sorted(RECORDED))
def test_env_runs_hash_as_recorded_before_the_kernels(team_size, steps, seed, field):
    got = env_run_hash(team_size=team_size, steps=steps, seed=seed, field=field)
    assert got == RECORDED[(team_size, steps, seed, field)]
