"""The cycle's numba kernels are compiled (or loaded from numba's disk cache) at the first
``reset()``, not inside a cycle: a cold compile takes seconds, and a match's stall watchdog
interrupts a cycle that runs over its limit (an interrupted compile also leaves numba without
the function, and every later match of the process fails). Run in a fresh interpreter, so that
no earlier test has compiled anything: after ``reset()`` a match with messages, kicks, falls
and a push adds no compiled signature to any of them, the env's nor the ``full`` team's."""

import ast
import subprocess
import sys

import pytest

CODE = """
import numpy as np
import teamenv
from comms import capacity_kernel
from locomotion import step_kernel
from teamenv.sim import kernels
from strategy.behaviours import kick_kernel, walk_kernel
from strategy.perception import cluster_kernel, reach_kernel, worldmodel_kernel
env = teamenv.parallel_env(field={field!r}, team_size={size}, left="full", right="chaser",
                           **{options!r})
env.reset(seed=3)
kernels_used = [step_kernel.step_bodies, capacity_kernel.hear_by_capacity,
                kernels.world_velocities, kernels.fill_heard, kernels.state_rows,
                kick_kernel.candidates, kick_kernel.choose, walk_kernel.walk_commands,
                reach_kernel.reach_rows, worldmodel_kernel.team_rows,
                cluster_kernel.cluster_stats, cluster_kernel.group_labels]
before = [len(k.signatures) for k in kernels_used]
falls = 0
for cycle in range(400):
    if cycle == 200:
        env.sim.bodies.push(0, np.array([3.0, 0.0]))  # a fall from a push
    env.step({{}})
    falls += int(np.count_nonzero(env.sim.bodies.fallen))
after = [len(k.signatures) for k in kernels_used]
print(repr((before, after, falls)))
"""


@pytest.mark.parametrize(("field", "size", "options"), [
    ("simspark", 11, {}),
    ("mj7v7", 7, {"observation_mode": "vision", "vision": "mj"}),
])
def test_no_kernel_compiles_inside_a_cycle(field, size, options):
    out = subprocess.run([sys.executable, "-c", CODE.format(field=field, size=size,
                                                            options=options)],
                         capture_output=True, text=True, check=True).stdout
    before, after, falls = ast.literal_eval(out.strip().splitlines()[-1])
    assert falls > 0  # the push toppled a body: the kernel ran its fall paths
    assert before[0] == 1  # the body kernel is compiled before the first cycle
    assert before[5:9] == [1, 1, 1, 1]  # the left team's kick choice, walks, ball reach
    if options.get("observation_mode") == "vision":  # its sighting windows' clustering
        assert before[10:] == [1, 1]
    assert after == before
