"""The viewer's local web server (stdlib ``http.server``, 127.0.0.1, a free port by default).

Routes (GET):

- ``/`` and ``/static/<file>``: the page (``index.html``, ``viewer.js``, ``viewer.css``),
  shipped as package data; nothing is built or downloaded at run time;
- ``/api/source``: what is being shown (``kind`` replay|tournament, ``path``,
  ``default_match``);
- ``/api/matches``: the matches that can be opened (a replay file: one, id 0);
- ``/api/matches/<id>/header``: field, teams, result, events, view cone and the blob layout;
- ``/api/matches/<id>/arrays/core`` and ``.../arrays/overlays``: the per-cycle arrays as
  two binary blobs, what playing needs and what the overlays add (``payload.py``);
- ``/api/matches/<id>/stats``: the match statistics (``teamenv.analytics``), 404 when the
  analytics package is not installed.

Errors answer JSON ``{"error": message}`` with 404 (unknown route or match) or 422 (a replay
or database that cannot be read).
"""

from __future__ import annotations

import json
import re
import threading
from functools import partial
from http import HTTPStatus
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from importlib import resources
from typing import Any
from urllib.parse import urlsplit

from teamenv.errors import TeamEnvError
from teamenv.replay import Replay
from teamenv.viewer.errors import ViewerError
from teamenv.viewer.payload import encode_replay
from teamenv.viewer.sources import ViewerSource

STATIC_FILES = {"index.html": "text/html; charset=utf-8",
                "viewer.js": "text/javascript; charset=utf-8",
                "viewer.css": "text/css; charset=utf-8"}
_MATCH_ROUTE = re.compile(r"^/api/matches/(-?\d+)/(header|arrays/core|arrays/overlays|stats)$")


def static_file(name: str) -> bytes:
    """The bytes of one of the page's files (package data ``teamenv/viewer/static``)."""
    return resources.files("teamenv.viewer").joinpath("static", name).read_bytes()


def match_stats(replay: Replay) -> dict[str, Any]:
    """``MatchStats.to_json()`` of ``replay``; ViewerError 404 when ``teamenv.analytics`` (or
    its stats) is not there."""
    try:
        from teamenv.analytics.stats import match_stats as compute
    except ImportError as exc:
        raise ViewerError(f"match statistics need teamenv.analytics ({exc})", status=404) from exc
    return compute(replay).to_json()


class _Handler(BaseHTTPRequestHandler):
    """Answers one request from the viewer's routes (see the module docstring)."""

    server_version = "teamenv-viewer"

    def __init__(self, *args: Any, viewer: ViewerServer, **kwargs: Any) -> None:
        self.viewer = viewer
        super().__init__(*args, **kwargs)

    def log_message(self, format: str, *args: Any) -> None:  # noqa: A002 - base signature
        if self.viewer.verbose:
            super().log_message(format, *args)

    def do_GET(self) -> None:  # noqa: N802 - http.server's name
        path = urlsplit(self.path).path
        try:
            self._route(path)
        except ViewerError as exc:
            self._json({"error": str(exc)}, exc.status)
        except TeamEnvError as exc:
            self._json({"error": str(exc)}, HTTPStatus.UNPROCESSABLE_ENTITY)
        except Exception as exc:  # noqa: BLE001 - the page shows it; the server keeps serving
            self.log_error("%s failed: %r", path, exc)
            self._json({"error": f"{path}: {type(exc).__name__}: {exc}"},
                       HTTPStatus.INTERNAL_SERVER_ERROR)

    def _route(self, path: str) -> None:
        source = self.viewer.source
        if path in ("/", "/index.html"):
            return self._static("index.html")
        if path.startswith("/static/"):
            return self._static(path[len("/static/"):])
        if path == "/favicon.ico":
            return self._send(b"", "image/x-icon", HTTPStatus.NO_CONTENT)
        if path == "/api/source":
            return self._json(source.describe())
        if path == "/api/matches":
            return self._json(source.matches())
        found = _MATCH_ROUTE.match(path)
        if found is None:
            raise ViewerError(f"no page {path!r}", status=404)
        match_id, what = int(found.group(1)), found.group(2)
        if what == "stats":
            return self._json(self.viewer.stats(match_id))
        header, blobs = self.viewer.encoded(match_id)
        if what == "header":
            return self._json(header)
        return self._send(blobs[what.split("/")[1]], "application/octet-stream")

    def _static(self, name: str) -> None:
        if name not in STATIC_FILES:
            raise ViewerError(f"no page '/static/{name}'", status=404)
        self._send(static_file(name), STATIC_FILES[name])

    def _json(self, value: Any, status: int = HTTPStatus.OK) -> None:
        self._send(json.dumps(value).encode(), "application/json", status)

    def _send(self, body: bytes, content_type: str, status: int = HTTPStatus.OK) -> None:
        try:
            self.send_response(status)
            self.send_header("Content-Type", content_type)
            self.send_header("Content-Length", str(len(body)))
            self.send_header("Cache-Control", "no-store")
            self.end_headers()
            self.wfile.write(body)
        except (BrokenPipeError, ConnectionResetError):
            pass  # the page went away (closed, reloaded) before its answer was ready


class ViewerServer:
    """Serves ``source`` on ``host:port`` (port 0: a free port; see ``url``).

    ``start()`` serves from a daemon thread, ``serve_forever()`` from the calling one;
    ``close()`` stops it. The open match's encoding and statistics are kept, so reloading the
    page is instant. ``prepare``: encode the match the page opens first in the background at
    once, so the page's first request finds it ready.
    """

    def __init__(self, source: ViewerSource, host: str = "127.0.0.1", port: int = 0,
                 verbose: bool = False, prepare: bool = True) -> None:
        self.source = source
        self.verbose = verbose
        self._encoded: dict[int, tuple[dict[str, Any], dict[str, bytes]]] = {}
        self._stats: dict[int, dict[str, Any]] = {}
        self._lock = threading.Lock()
        try:
            self.httpd = ThreadingHTTPServer((host, port), partial(_Handler, viewer=self))
        except OSError as exc:
            raise ViewerError(f"cannot serve on {host}:{port}: {exc}") from exc
        self.httpd.daemon_threads = True
        self._thread: threading.Thread | None = None
        if prepare and source.default_match() is not None:
            threading.Thread(target=self._prepare, args=(source.default_match(),), daemon=True,
                             name="teamenv-viewer-prepare").start()

    def _prepare(self, match_id: int) -> None:
        try:
            self.encoded(match_id)
        except Exception:  # noqa: BLE001, S110 - the page's own request reports it
            pass

    @property
    def url(self) -> str:
        host, port = self.httpd.server_address[:2]
        return f"http://{host}:{port}/"

    def encoded(self, match_id: int) -> tuple[dict[str, Any], dict[str, bytes]]:
        """(header, {group: blob}) of one match, encoded once."""
        with self._lock:
            if match_id not in self._encoded:
                self._encoded = {match_id: encode_replay(self.source.replay(match_id), match_id)}
            return self._encoded[match_id]

    def stats(self, match_id: int) -> dict[str, Any]:
        """``match_stats`` of one match, computed once (a full match takes ~1 s)."""
        if match_id not in self._stats:
            self._stats = {match_id: match_stats(self.source.replay(match_id))}
        return self._stats[match_id]

    def start(self) -> ViewerServer:
        self._thread = threading.Thread(target=self.httpd.serve_forever, daemon=True,
                                        name="teamenv-viewer")
        self._thread.start()
        return self

    def serve_forever(self) -> None:
        self.httpd.serve_forever()

    def close(self) -> None:
        if self._thread is not None:
            self.httpd.shutdown()
            self._thread.join()
            self._thread = None
        self.httpd.server_close()

    def __enter__(self) -> ViewerServer:
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()
