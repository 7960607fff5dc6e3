"""The GIL is released during a solve, and Ctrl-C stops a long one."""

import signal
import subprocess
import sys
import threading
import time

import crawlopt as co

LONG = """
import crawlopt as co
c = co.Crawler(blocks=6, mu_backward=1.63)
print("started", flush=True)
co.optimize(c, co.GaitProblem(period=10), method="phase", phases=4, time_limit=120)
print("finished", flush=True)
"""


def test_a_python_thread_runs_during_a_solve():
    ticks = []
    done = threading.Event()

    def count():
        while not done.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.005)

    t = threading.Thread(target=count)
    m = co.load("examples/three_blocks_gait.toml")
    t.start()
    began = time.perf_counter()
    co.optimize(m.crawler, m.gait_problem)
    ended = time.perf_counter()
    done.set()
    t.join()
    during = [x for x in ticks if began < x < ended]
    # The solve takes about a second; with the GIL held the thread would not tick at all.
    assert len(during) >= 0.2 * (ended - began) / 0.005, (len(during), ended - began)


def test_ctrl_c_stops_a_long_optimize_within_two_seconds():
    p = subprocess.Popen(
        [sys.executable, "-c", LONG],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    assert p.stdout.readline().strip() == "started"
    time.sleep(1.5)
    sent = time.perf_counter()
    p.send_signal(signal.SIGINT)
    try:
        p.wait(timeout=10)
    finally:
        p.kill()
    elapsed = time.perf_counter() - sent
    err = p.stderr.read()
    assert "KeyboardInterrupt" in err, err
    assert "finished" not in p.stdout.read()
    assert elapsed < 2.0, elapsed


OWN_HANDLER = """
import signal
import crawlopt as co
seen = []
signal.signal(signal.SIGINT, lambda *a: seen.append(1))
m = co.load("examples/three_blocks_gait.toml")
print("started", flush=True)
r = co.optimize(m.crawler, m.gait_problem, method="phase", phases=5)
print("finished", round(r.objective, 9), len(seen), flush=True)
"""


def test_a_program_with_its_own_sigint_handler_keeps_it():
    # Ctrl-C cancels a job only where it would raise KeyboardInterrupt: a handler of the
    # program's own is called instead (once the job is done) and the job runs to its end.
    p = subprocess.Popen(
        [sys.executable, "-c", OWN_HANDLER],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    assert p.stdout.readline().strip() == "started"
    time.sleep(0.2)
    p.send_signal(signal.SIGINT)
    out, err = p.communicate(timeout=60)
    assert out.split() == ["finished", "2.6", "1"], (out, err)


def test_a_progress_callback_that_raises_stops_the_job_with_its_exception():
    m = co.load("examples/three_blocks_gait.toml")
    seen = []

    def fail(event):
        seen.append(event)
        raise RuntimeError("enough")

    began = time.perf_counter()
    try:
        co.optimize(m.crawler, m.gait_problem, method="phase", phases=8, progress=fail)
    except RuntimeError as e:
        assert str(e) == "enough"
    else:
        raise AssertionError("the callback's exception was not raised")
    # The job was stopped at its next check, not run to its end (K = 8 takes about 18 s).
    assert len(seen) == 1, seen
    assert time.perf_counter() - began < 5.0
