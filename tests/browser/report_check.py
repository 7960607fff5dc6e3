#!/usr/bin/env python3
"""Checks a crawlopt HTML report in headless Chromium, as a reader would see it.

Opens the report from disk (file://), waits for the animation to run, takes two screenshots at
two times, and asserts from the page (the DOM as rendered, not the HTML source) that

  * the animation plays: its time advances between the screenshots, and Pause stops it;
  * after k periods (k = 1 .. all shown) the blocks drawn on screen have advanced by k times the
    displacement per period that the page reports, within a pixel;
  * the page fetched nothing from the network and raised no console error or exception.

Python standard library only: Chromium is driven through its DevTools protocol over a pipe
(--remote-debugging-pipe: JSON messages separated by NUL bytes on file descriptors 3 and 4), so
no driver or package is needed beyond Debian's `chromium`.

Usage: report_check.py REPORT.html [--screenshots DIR] [--chromium PATH]
Prints one line per check and a summary line in the format of `cargo test`
("test result: ok. N passed; M failed;") that scripts/test counts.
"""

import argparse
import base64
import fcntl
import json
import os
import pathlib
import select
import shutil
import subprocess
import sys
import tempfile
import time

CHROMIUM_FLAGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--disable-extensions",
    "--hide-scrollbars",
    "--remote-debugging-pipe",
]


class Browser:
    """A headless Chromium driven over the DevTools pipe."""

    def __init__(self, chromium):
        self.profile = tempfile.mkdtemp(prefix="crawlopt-chromium-")
        to_child_r, self.to_child = os.pipe()
        self.from_child, from_child_w = os.pipe()
        # Move the child's ends above 10 so that dup2 onto 3 and 4 cannot clobber them.
        hi_r = fcntl.fcntl(to_child_r, fcntl.F_DUPFD, 10)
        hi_w = fcntl.fcntl(from_child_w, fcntl.F_DUPFD, 10)
        os.close(to_child_r)
        os.close(from_child_w)

        def child_fds():
            os.dup2(hi_r, 3)
            os.dup2(hi_w, 4)

        self.proc = subprocess.Popen(
            [chromium, *CHROMIUM_FLAGS, f"--user-data-dir={self.profile}", "about:blank"],
            preexec_fn=child_fds,
            close_fds=False,
            stdin=subprocess.DEVNULL,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        os.close(hi_r)
        os.close(hi_w)
        self.buf = b""
        self.next_id = 0
        self.events = []
        self.session = None

    def _read_message(self, deadline):
        while b"\0" not in self.buf:
            left = deadline - time.time()
            if left <= 0:
                raise TimeoutError("no answer from Chromium")
            ready, _, _ = select.select([self.from_child], [], [], left)
            if ready:
                chunk = os.read(self.from_child, 1 << 20)
                if not chunk:
                    raise RuntimeError("Chromium closed the DevTools pipe (did it start?)")
                self.buf += chunk
        msg, self.buf = self.buf.split(b"\0", 1)
        return json.loads(msg)

    def send(self, method, params=None, session=True, timeout=30.0):
        self.next_id += 1
        msg = {"id": self.next_id, "method": method, "params": params or {}}
        if session and self.session:
            msg["sessionId"] = self.session
        os.write(self.to_child, json.dumps(msg).encode() + b"\0")
        deadline = time.time() + timeout
        while True:
            m = self._read_message(deadline)
            if m.get("id") == self.next_id:
                if "error" in m:
                    raise RuntimeError(f"{method}: {m['error']}")
                return m.get("result", {})
            self.events.append(m)

    def pump(self, seconds):
        """Collects events for `seconds`."""
        deadline = time.time() + seconds
        while True:
            try:
                self.events.append(self._read_message(deadline))
            except TimeoutError:
                return

    def wait_event(self, method, timeout=30.0):
        deadline = time.time() + timeout
        for e in self.events:
            if e.get("method") == method:
                return e
        while True:
            e = self._read_message(deadline)
            self.events.append(e)
            if e.get("method") == method:
                return e

    def eval(self, expression):
        r = self.send(
            "Runtime.evaluate",
            {"expression": expression, "returnByValue": True, "awaitPromise": True},
        )
        if "exceptionDetails" in r:
            raise RuntimeError(f"page script failed: {r['exceptionDetails']}")
        return r["result"].get("value")

    def close(self):
        try:
            self.send("Browser.close", session=False, timeout=5)
        except Exception:
            pass
        try:
            self.proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        shutil.rmtree(self.profile, ignore_errors=True)


# Screen position of the blocks and the on-screen scale, measured from the rendered page.
MEASURE = """(() => {
  const svg = document.getElementById('crawler-svg');
    const vb = svg.viewBox.baseVal;
  const screenPerUnit = Number(svg.dataset.pxPerUnit) * svg.clientWidth / vb.width; // clientWidth: without the border
  const rects = [...svg.querySelectorAll('rect.block')].map(r => r.getBoundingClientRect());
  const mean = rects.reduce((a, r) => a + r.left + r.width / 2, 0) / rects.length;
  const st = document.getElementById('anim-state').dataset;
  return {mean, screenPerUnit, blocks: rects.length, t: Number(st.t), y: Number(st.y)};
})()"""


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("report")
    ap.add_argument("--screenshots", default=None)
    ap.add_argument("--chromium", default=shutil.which("chromium") or "chromium")
    args = ap.parse_args()
    report = pathlib.Path(args.report).resolve()
    if not report.is_file():
        print(f"error: {report.name}: no such report", file=sys.stderr)
        return 2
    shots = pathlib.Path(args.screenshots) if args.screenshots else report.parent
    shots.mkdir(parents=True, exist_ok=True)

    passed, failed = 0, 0

    def check(name, ok, detail=""):
        nonlocal passed, failed
        if ok:
            passed += 1
        else:
            failed += 1
        print(f"test browser::{name} ... {'ok' if ok else 'FAILED'}{'  (' + detail + ')' if detail else ''}")

    b = Browser(args.chromium)
    try:
        targets = b.send("Target.getTargets", session=False)["targetInfos"]
        page = next(t for t in targets if t["type"] == "page")
        b.session = b.send(
            "Target.attachToTarget", {"targetId": page["targetId"], "flatten": True}, session=False
        )["sessionId"]
        for domain in ("Runtime", "Log", "Page", "Network"):
            b.send(f"{domain}.enable")
        b.send(
            "Emulation.setDeviceMetricsOverride",
            {"width": 1200, "height": 1000, "deviceScaleFactor": 1, "mobile": False},
        )
        b.send("Page.navigate", {"url": report.as_uri()})
        b.wait_event("Page.loadEventFired")

        ready = False
        deadline = time.time() + 15
        while time.time() < deadline and not ready:
            ready = b.eval("document.getElementById('anim-state')?.dataset.ready === '1'")
            if not ready:
                b.pump(0.2)
        check("animation_starts", bool(ready))
        if not ready:
            raise RuntimeError("the animation did not start")
        b.eval("document.getElementById('animation').scrollIntoView()")

        # Two screenshots at two times while the animation plays.
        b.pump(1.0)
        times = []
        for k in (1, 2):
            state = b.eval(MEASURE)
            times.append(state["t"])
            png = b.send("Page.captureScreenshot", {"format": "png"})["data"]
            (shots / f"report-{k}.png").write_bytes(base64.b64decode(png))
            b.pump(1.5)
        check(
            "animation_plays",
            times[1] > times[0] > 0,
            f"t = {times[0]:.3f} then {times[1]:.3f}",
        )

        # Pause stops the clock.
        b.eval("document.getElementById('anim-play').click()")
        t0 = b.eval(MEASURE)["t"]
        b.pump(0.8)
        t1 = b.eval(MEASURE)["t"]
        check("pause_stops", t0 == t1, f"t = {t0:.3f} then {t1:.3f}")

        # Displacement: move the time slider to whole periods, measure the blocks on screen.
        st = b.eval("({...document.getElementById('anim-state').dataset})")
        period, periods = float(st["period"]), int(st["periods"])
        shown = b.eval(
            "Number(document.getElementById('displacement-per-period').dataset.value)"
        )
        check(
            "reported_displacement_consistent",
            abs(shown - float(st["displacement"])) <= 1e-12 * max(1, abs(shown)),
            f"{shown}",
        )
        check("moves", abs(shown) > 1e-9, f"displacement per period {shown}")

        def at(t):
            return b.eval(
                "(() => { const s = document.getElementById('anim-time'); "
                f"s.value = String({t!r}); s.dispatchEvent(new Event('input')); "
                f"return {MEASURE}; }})()"
            )

        start = at(0.0)
        worst = 0.0
        for k in range(1, periods + 1):
            now = at(k * period)
            moved = (now["mean"] - start["mean"]) / now["screenPerUnit"]
            want = k * shown
            px_err = abs(moved - want) * now["screenPerUnit"]
            worst = max(worst, px_err)
            check(
                f"advance_after_{k}_periods",
                px_err <= 0.5 and abs(now["y"] - want) <= 1e-6 * max(1, abs(want)),
                f"blocks moved {moved:.6f}, readout {now['y']:.6f}, expected {want:.6f}",
            )
        check("blocks_drawn", start["blocks"] >= 2, f"{start['blocks']} blocks")

        b.pump(0.3)
        errors = []
        requests = []
        for e in b.events:
            m, p = e.get("method"), e.get("params", {})
            if m == "Runtime.exceptionThrown":
                errors.append(p["exceptionDetails"].get("text", "exception"))
            elif m == "Runtime.consoleAPICalled" and p.get("type") in ("error", "assert"):
                errors.append(" ".join(str(a.get("value", "")) for a in p.get("args", [])))
            elif m == "Log.entryAdded" and p["entry"].get("level") == "error":
                errors.append(p["entry"].get("text", ""))
            elif m == "Network.requestWillBeSent":
                requests.append(p["request"]["url"])
        check("no_console_errors", not errors, "; ".join(errors)[:300])
        remote = [u for u in requests if not u.startswith(("file:", "data:", "about:"))]
        check("no_network", not remote, ", ".join(remote)[:300])
    except Exception as e:  # a broken page or browser is a failed check, not a traceback
        check("browser_session", False, f"{type(e).__name__}: {e}")
    finally:
        b.close()

    status = "ok" if failed == 0 else "FAILED"
    print(f"screenshots: {shots / 'report-1.png'}, {shots / 'report-2.png'}")
    print(f"test result: {status}. {passed} passed; {failed} failed; (browser check of {report.name})")
    return 0 if failed == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
