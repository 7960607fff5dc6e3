"""The documentation site's link and sample checks (run by scripts/docs; standard library only).

links: every <a href> and <img src> of the built MkDocs pages (not of the copied rustdoc under
rust/, whose own links rustdoc checks) that stays inside the site must name a file that exists
and, with a #fragment, an element with that id in it. External links (with a scheme) are not
fetched.

samples: a fenced code block whose fence is preceded by the line `<!-- sample -->` is run:
`sh` in bash -euo pipefail (the crawlopt binary first on PATH), `python` in the interpreter given
by --python; each in a fresh temporary directory holding a copy of examples/, with a time limit.

Prints one "test result:" line per group; exits 1 when anything failed.
"""

from __future__ import annotations

import argparse
import html.parser
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from urllib.parse import unquote, urlsplit

SAMPLE_MARK = "<!-- sample -->"
SAMPLE_SECONDS = 600


class _Page(html.parser.HTMLParser):
    def __init__(self) -> None:
        super().__init__()
        self.ids: set[str] = set()
        self.links: list[str] = []

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        for key in ("id", "name"):
            if a.get(key):
                self.ids.add(a[key])
        if tag == "a" and a.get("href"):
            self.links.append(a["href"])
        if tag == "img" and a.get("src"):
            self.links.append(a["src"])


def _parse(path: Path, cache: dict) -> _Page:
    if path not in cache:
        page = _Page()
        page.feed(path.read_text(encoding="utf-8", errors="replace"))
        cache[path] = page
    return cache[path]


def check_links(site: Path) -> tuple[int, list[str]]:
    cache: dict = {}
    checked: set[tuple[Path, str]] = set()
    failures: list[str] = []
    rust = site / "rust"
    # 404.html is served in place of any missing page, so MkDocs writes its links from the site's
    # root ("/index.html"), not relative to a place on disk: not checked here.
    pages = [p for p in site.rglob("*.html") if rust not in p.parents and p.name != "404.html"]
    for page in sorted(pages):
        for href in _parse(page, cache).links:
            parts = urlsplit(href)
            if parts.scheme or parts.netloc or href.startswith(("mailto:", "javascript:")):
                continue
            target = page if not parts.path else (page.parent / unquote(parts.path)).resolve()
            if target.is_dir():
                target = target / "index.html"
            where = f"{page.relative_to(site)}: {href}"
            if (page, href) in checked:
                continue
            checked.add((page, href))
            if not target.is_file():
                failures.append(f"{where}: no such file")
                continue
            if parts.fragment and target.suffix == ".html":
                if unquote(parts.fragment) not in _parse(target, cache).ids:
                    failures.append(f"{where}: no anchor #{parts.fragment}")
    return len(checked), failures


def samples(docs: Path) -> list[tuple[str, str, str]]:
    """(where, language, code) for every marked block, in page order."""
    found = []
    for md in sorted(docs.rglob("*.md")):
        lines = md.read_text(encoding="utf-8").split("\n")
        for i, line in enumerate(lines):
            if line.strip() != SAMPLE_MARK:
                continue
            fence = lines[i + 1] if i + 1 < len(lines) else ""
            m = re.match(r"^(`{3,})\s*([A-Za-z]+)", fence)
            where = f"{md.relative_to(docs.parent)}:{i + 2}"
            if not m:
                found.append((where, "", "no fenced block after the sample mark"))
                continue
            end = next(
                (j for j in range(i + 2, len(lines)) if lines[j].startswith(m.group(1))), None
            )
            if end is None:
                found.append((where, "", "the fenced block is not closed"))
                continue
            found.append((where, m.group(2), "\n".join(lines[i + 2 : end]) + "\n"))
    return found


def run_samples(docs: Path, examples: Path, python: str) -> tuple[int, list[str]]:
    failures = []
    found = samples(docs)
    for where, lang, code in found:
        if lang in ("sh", "bash"):
            cmd = ["bash", "-euo", "pipefail", "-c", code]
        elif lang == "python":
            cmd = [python, "-c", code]
        else:
            failures.append(f"{where}: {code if not lang else f'cannot run a {lang!r} sample'}")
            continue
        with tempfile.TemporaryDirectory(prefix="crawlopt-docs-sample-") as tmp:
            shutil.copytree(examples, Path(tmp) / "examples")
            began = time.monotonic()
            try:
                run = subprocess.run(
                    cmd,
                    cwd=tmp,
                    capture_output=True,
                    text=True,
                    timeout=SAMPLE_SECONDS,
                    env=dict(os.environ, MPLBACKEND="Agg"),
                )
                ok, detail = run.returncode == 0, f"exit {run.returncode}"
                output = run.stdout[-2000:] + run.stderr[-2000:]
            except (OSError, subprocess.TimeoutExpired) as e:
                ok, detail, output = False, str(e), ""
            seconds = time.monotonic() - began
        print(
            f"docs sample {where} ({lang}): {'ok' if ok else 'FAILED'} ({seconds:.1f} s)",
            file=sys.stderr,
        )
        if not ok:
            failures.append(f"{where}: {detail}\n{output}")
    return len(found), failures


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--site", type=Path, required=True)
    ap.add_argument("--docs", type=Path, required=True)
    ap.add_argument("--examples", type=Path, required=True)
    ap.add_argument("--python", required=True)
    a = ap.parse_args()
    bad = False
    if (a.site / "index.html").is_file():
        n, failures = check_links(a.site)
    else:
        n, failures = 0, ["the site was not built"]
    for f in failures:
        print(f"docs link: {f}", file=sys.stderr)
    print(
        f"test result: docs. {n - len(failures) if n else 0} passed; {len(failures)} failed "
        f"(links: internal links of the built pages)"
    )
    bad |= bool(failures)
    n, failures = run_samples(a.docs, a.examples, a.python)
    for f in failures:
        print(f"docs sample: {f}", file=sys.stderr)
    print(
        f"test result: docs. {n - len(failures)} passed; {len(failures)} failed "
        f"(samples: marked code blocks run)"
    )
    bad |= bool(failures) or n == 0
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
