"""Vision, say-channel and locomotion profiles are held the same way: a ``paramkit.Registry``
each (``teamenv.VISION_PROFILES``, ``comms.PROFILES``, ``locomotion.PROFILES``), so a user adds
one with ``register(name, value)`` and the env takes it by name; an unknown name is its
package's error, listing the names."""

from __future__ import annotations

from dataclasses import replace

import pytest

import comms
import locomotion
import teamenv
from comms.errors import ChannelError
from locomotion.profile import PROFILE_DIR
from paramkit import Registry
from teamenv.errors import ConfigError

REGISTRIES = {"vision": teamenv.VISION_PROFILES, "channel": comms.PROFILES,
              "locomotion": locomotion.PROFILES}


@pytest.mark.parametrize("kind", list(REGISTRIES))
def test_every_kind_of_profile_is_a_registry(kind):
    registry = REGISTRIES[kind]
    assert isinstance(registry, Registry)
    assert registry.names() == sorted(registry) and len(registry.names()) >= 2


def test_shipped_names_are_the_registered_ones():
    assert set(teamenv.VISION_PROFILES.names()) == {"simspark", "mj", "mj_noisy"}
    assert set(comms.PROFILES.names()) == {"simspark", "mj"}
    assert locomotion.PROFILES.names() == locomotion.shipped_profiles()


def test_a_profile_added_to_each_registry_is_taken_by_the_env():
    wide = replace(teamenv.VISION_PROFILES["mj"], fov_horizontal_deg=180.0)
    short = replace(comms.SIMSPARK, name="short_say", max_chars=4)
    teamenv.VISION_PROFILES.register("test_wide", wide)
    comms.PROFILES.register("short_say", short)
    locomotion.PROFILES.register("test_robot", PROFILE_DIR / "nao_simspark.json")
    try:
        env = teamenv.parallel_env(team_size=1, observation_mode="vision", vision="test_wide",
                                   channel="short_say", locomotion_profile="test_robot")
        assert env.sim.vision.config == wide
        assert env.sim.channel.profile == short
        assert locomotion.load_profile("test_robot").path == str(PROFILE_DIR / "nao_simspark.json")
        assert env.sim.bodies.profile.name == "nao_simspark"
        env.reset(seed=0)
        env.step({a: {"say": "abcd"} for a in env.agents})
    finally:
        teamenv.VISION_PROFILES.unregister("test_wide")
        comms.PROFILES.unregister("short_say")
        locomotion.PROFILES.unregister("test_robot")
    assert "test_wide" not in teamenv.VISION_PROFILES


def test_an_unknown_name_is_the_packages_error_listing_the_names():
    with pytest.raises(ConfigError, match=r"unknown vision profile 'moon'; choose one of "
                                          r"\['mj', 'mj_noisy', 'simspark'\]"):
        teamenv.parallel_env(observation_mode="vision", vision="moon")
    with pytest.raises(ChannelError, match=r"unknown channel profile 'moon'; choose one of "
                                           r"\['mj', 'simspark'\]"):
        comms.get_profile("moon")
    with pytest.raises(locomotion.ProfileError, match="no such shipped profile or registered "
                                                      "name .*t1_mj"):
        locomotion.load_profile("moon")
    with pytest.raises(ConfigError, match="locomotion_profile"):
        teamenv.parallel_env(locomotion_profile="moon")
