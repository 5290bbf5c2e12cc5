"""Start a private Ray instance or join a named cluster (the ``ray`` extra).

``ray.init(address=None, num_cpus=N)`` first looks for a cluster on the machine (a running
``ray start --head``, or the address a stopped one left in ``/tmp/ray/ray_current_cluster``)
and then refuses ``num_cpus`` ("When connecting to an existing cluster, num_cpus and num_gpus
must not be provided"). So teamenv never passes None: with no address it asks for Ray's
``"local"`` (a new instance of its own, whatever else runs on the machine), and it joins a
cluster only when told to (``"auto"``, ``"HOST:PORT"``, ``"ray://HOST:PORT"``), without
resource arguments, which belong to the cluster.
"""

from __future__ import annotations

import socket
from typing import Any

from teamenv.errors import MissingExtraError
from teamenv.tournament.errors import TournamentConfigError

#: what the callers accept for "start a private instance"
LOCAL = "local"


class RayClusterError(TournamentConfigError):
    """The Ray cluster named by an address could not be joined."""


def init_ray(address: str | None = None, num_cpus: int | None = None, *,
             local_system_config: dict[str, Any] | None = None, **init_kwargs: Any) -> None:
    """``ray.init`` for teamenv: ``address`` None or ``"local"`` starts a private local
    instance with ``num_cpus`` CPUs (and ``local_system_config`` as Ray's ``_system_config``);
    any other address joins that cluster and must not come with ``num_cpus``. A cluster that
    cannot be joined raises ``RayClusterError`` naming the address, in one line."""
    try:
        import ray
    except ImportError:
        raise MissingExtraError("ray", "ray", "Ray") from None
    if address is None or address == LOCAL:
        extra = {"_system_config": local_system_config} if local_system_config else {}
        ray.init(address=LOCAL, num_cpus=num_cpus, **extra, **init_kwargs)
        return
    if not isinstance(address, str) or not address.strip():
        raise RayClusterError(f"Ray address {address!r}: give 'local', 'auto', HOST:PORT or "
                              "ray://HOST:PORT")
    if num_cpus is not None:
        raise RayClusterError(f"Ray address {address!r}: num_cpus={num_cpus} applies to a "
                              "local instance only (a cluster has its own resources)")
    _check_reachable(address)
    try:
        ray.init(address=address, **init_kwargs)
    except (ConnectionError, TimeoutError, ValueError, RuntimeError) as exc:
        first_line = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        raise RayClusterError(f"cannot join the Ray cluster at {address!r}: {first_line}") \
            from None


#: seconds to wait for a TCP connection to a cluster's address before calling it unreachable
CONNECT_TIMEOUT_S = 5.0


def _check_reachable(address: str) -> None:
    """Refuse an address nobody answers on, at once: ``ray.init`` itself retries a dead GCS
    address for minutes (seen: > 200 s for 127.0.0.1:9), and ``"auto"`` goes to whatever
    address a stopped cluster left in ``ray_current_cluster``."""
    target = _resolve(address)
    if target is None:
        return
    host, _, port = target.rpartition(":")
    try:
        with socket.create_connection((host.strip("[]"), int(port)), timeout=CONNECT_TIMEOUT_S):
            pass
    except (OSError, ValueError) as exc:
        shown = address if target == address else f"{address} -> {target}"
        raise RayClusterError(f"cannot join the Ray cluster at {shown!r}: nothing answers "
                              f"there ({type(exc).__name__}: {exc})") from None


def _resolve(address: str) -> str | None:
    """HOST:PORT that ``address`` stands for, or None when it cannot be told beforehand."""
    if address.startswith("ray://"):
        return address[len("ray://"):].split("/", 1)[0] or None
    if address == "auto":
        try:  # Ray's own lookup (RAY_ADDRESS, ray_current_cluster, running GCS processes)
            from ray._private.services import get_ray_address_from_environment
        except ImportError:  # private API moved: let ray.init find it
            return None
        try:
            found = get_ray_address_from_environment("auto", None)
        except ConnectionError as exc:
            raise RayClusterError(f"cannot join the Ray cluster at 'auto': {exc}") from None
        return found if found and found != "auto" else None
    return address if ":" in address else None
