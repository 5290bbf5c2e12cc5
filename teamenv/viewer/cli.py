"""``teamenv view REPLAY|TOURNAMENT.sqlite``: serve the replay viewer and open it in a browser."""

from __future__ import annotations

import argparse
import webbrowser
from pathlib import Path


def add_parser(subparsers: argparse._SubParsersAction) -> None:
    """Register ``view`` on the ``teamenv`` parser (sets ``func(args) -> exit code``)."""
    p = subparsers.add_parser(
        "view", help="watch a replay or a tournament's matches in the browser (local web page)",
        description="Serve the replay viewer on 127.0.0.1 and open it in the default browser. "
                    "PATH is a replay (.npz, from `teamenv match --replay`) or a tournament "
                    "database (SQLite), whose matches are listed to open.")
    p.add_argument("path", type=Path, help="replay .npz or tournament .sqlite")
    p.add_argument("--port", type=int, default=0, help="port on 127.0.0.1 (default: a free one)")
    p.add_argument("--host", default="127.0.0.1",
                   help="address to listen on (default 127.0.0.1: this machine only)")
    p.add_argument("--no-browser", action="store_true", help="print the address, open nothing")
    p.add_argument("--verbose", action="store_true", help="log every request")
    p.set_defaults(func=_run)


def _run(args: argparse.Namespace) -> int:
    from teamenv.viewer.errors import ViewerError
    from teamenv.viewer.server import ViewerServer
    from teamenv.viewer.sources import open_source

    if not 0 <= args.port <= 65535:
        raise ViewerError(f"--port: {args.port} is not a port number (0-65535; 0: a free one)")
    source = open_source(args.path)  # a bad file fails here, before anything is served
    server = ViewerServer(source, host=args.host, port=args.port, verbose=args.verbose)
    print(f"teamenv viewer: {source.kind} {str(args.path)!r} at {server.url} (Ctrl-C to stop)",
          flush=True)
    if not args.no_browser and not webbrowser.open(server.url):
        print("teamenv viewer: no browser to open here; open the address above yourself",
              flush=True)
    try:
        server.serve_forever()
    except KeyboardInterrupt:
        pass
    finally:
        server.close()
    return 0
