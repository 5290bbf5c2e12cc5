"""The infos a step returns: per agent, only what happened to it this cycle."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

import numpy as np

from teamenv.lazy import LazyInfos
from teamenv.sim.playmode import PlayMode
from teamenv.teams import SIDES

if TYPE_CHECKING:
    from teamenv.sim.simulation import CycleReport


def step_infos(agents: list[str], report: CycleReport, dropped: Mapping[str, list[str]],
               names: Sequence[str], play_mode: int) -> dict[str, dict]:
    """Each agent's info after a step of ``report``: only what happened to it, in this key
    order: ``dropped`` (its action's lenient drops, from ``dropped``), ``beam_refused`` (the
    play mode that refused it; ``play_mode`` is the referee's), ``message_dropped`` (its
    messages' drops, listed on first use: ``teamenv.lazy.LazyInfos``), ``goal`` (the side
    that scored). ``names``: the agent of each player index."""
    infos: dict[str, dict] = {a: {} for a in agents}
    if not agents:
        return infos
    for agent, problems in dropped.items():
        if agent in infos:
            infos[agent]["dropped"] = problems
    for i in report.beams_refused:
        if names[i] in infos:
            infos[names[i]]["beam_refused"] = PlayMode(play_mode).name
    for event in report.referee:
        if event.kind == "goal":
            for a in agents:
                infos[a]["goal"] = SIDES[event.team]
    delivery = report.delivery
    if delivery is None or not delivery.has_drops():
        return infos
    # Message drops (often hundreds a cycle when everybody speaks) are listed on first use.
    return LazyInfos(infos, lambda base: add_message_drops(base, names, report))


def add_message_drops(infos: dict[str, dict], names: Sequence[str], report: CycleReport) -> None:
    """Put each speaker's ``message_dropped`` list into ``infos`` (a plain dict's storage), in
    the key order of an eagerly built info: dropped, beam_refused, message_dropped, goal. Each
    list holds the speaker's drops in ``report.dropped`` order, one new dict per drop."""
    speaker, listener, reason = report.delivery.drop_arrays()
    if not speaker.size:
        return
    order = np.argsort(speaker, kind="stable")  # by speaker, each in report.dropped order
    speaker = speaker[order]
    named = np.array([*names, None], dtype=object)  # listener -1 (nobody) -> None
    drops = [{"listener": who, "reason": why}
             for who, why in zip(named[listener[order]].tolist(), reason[order].tolist(),
                                 strict=True)]
    starts = [0, *(np.flatnonzero(speaker[1:] != speaker[:-1]) + 1).tolist()]
    ends = [*starts[1:], len(drops)]
    get, n_names = dict.get, len(names)
    for index, a, b in zip(speaker[starts].tolist(), starts, ends, strict=True):
        info = get(infos, names[index]) if 0 <= index < n_names else None
        if info is None:
            continue
        if "goal" in info:
            goal = info.pop("goal")
            info["message_dropped"] = drops[a:b]
            info["goal"] = goal
        else:
            info["message_dropped"] = drops[a:b]
