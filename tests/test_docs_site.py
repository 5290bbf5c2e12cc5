"""The documentation site builds with `mkdocs build --strict`, offline, and the README's links resolve.

Strict mode turns every warning into a failure: a broken link or anchor between pages, a page
left out of the nav, an API reference (mkdocstrings) that cannot be resolved.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
# An HTTP(S) proxy nobody listens on: a build step that tried to download would fail.
OFFLINE = {"HTTP_PROXY": "http://127.0.0.1:9", "HTTPS_PROXY": "http://127.0.0.1:9",
           "http_proxy": "http://127.0.0.1:9", "https_proxy": "http://127.0.0.1:9",
           "NO_MKDOCS_2_WARNING": "1"}


@pytest.fixture(scope="module")
def site(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("site")
    run = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(out)],
        cwd=ROOT, env={**os.environ, **OFFLINE}, capture_output=True, text=True, timeout=600,
    )
    warnings = [ln for ln in run.stderr.splitlines() if ln.startswith(("WARNING", "ERROR"))]
    assert run.returncode == 0 and not warnings, (
        f"mkdocs build --strict failed (exit {run.returncode}):\n" + "\n".join(warnings)
        + "\n" + run.stderr[-3000:]
    )
    return out


def test_site_builds_strict_with_every_page(site: Path) -> None:
    pages = sorted(p.relative_to(ROOT / "docs").with_suffix("").as_posix()
                   for p in (ROOT / "docs").rglob("*.md"))
    assert "index" in pages and any(p.startswith("tutorials/") for p in pages)
    for page in pages:
        # mkdocs builds dir/index.md into dir/index.html, any other page.md into page/index.html
        is_index = page == "index" or page.endswith("/index")
        html = site / (page.removesuffix("index") if is_index else page + "/") / "index.html"
        assert html.is_file(), f"docs/{page}.md was not built into {html}"


def test_api_reference_is_generated_from_docstrings(site: Path) -> None:
    html = (site / "api/teamenv/index.html").read_text(encoding="utf-8")
    # the docstring of teamenv.env.parallel_env and of a class rendered with its members
    assert 'id="teamenv.env.parallel_env"' in html
    assert 'id="teamenv.teams.TeamContext"' in html
    comms_html = (site / "api/comms/index.html").read_text(encoding="utf-8")
    assert 'id="comms.schema.Schema.encode"' in comms_html


def test_site_loads_nothing_from_other_hosts(site: Path) -> None:
    for html in site.rglob("*.html"):
        text = html.read_text(encoding="utf-8")
        assert "fonts.googleapis.com" not in text and "fonts.gstatic.com" not in text, html


def test_readme_links_point_at_files_that_exist() -> None:
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    targets = re.findall(r"\]\(([^)#\s]+)(?:#[^)]*)?\)", text)
    local = [t for t in targets if "://" not in t]
    assert len(local) >= 10  # the README is mostly links into the site
    missing = [t for t in local if not (ROOT / t).exists()]
    assert not missing, f"README.md links to missing files: {missing}"
