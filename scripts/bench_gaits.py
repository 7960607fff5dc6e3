"""Driver of scripts/bench-gaits (standard library only): runs crawlopt and the peers on the same
instances, one at a time on one thread, and prints one table per comparison."""
import json
import os
import subprocess
import sys
import tempfile
import time

crawlopt, peers, peer_python = sys.argv[1:4]
time_limit = float(os.environ["TIME_LIMIT"])
starts = int(os.environ["STARTS"])
env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")


def mu_backward(n):
    return 1.6 if n == 5 else 1.5


def model_file(n, tmp):
    path = os.path.join(tmp, f"n{n}.toml")
    with open(path, "w") as f:
        f.write(f"[crawler]\nblocks = {n}\nstiffness = 1.0\nmu_forward = 1.0\n"
                f"mu_backward = {mu_backward(n)}\n\n[gait]\nperiod = 10.0\n"
                "max_actuator_speed = 1.0\ncost = { kind = \"none\" }\n")
    return path


def ours(args):
    t0 = time.perf_counter()
    out = subprocess.run([crawlopt, "optimize", *args, "--json"], capture_output=True,
                         text=True, env=env)
    wall = time.perf_counter() - t0
    if out.returncode != 0:
        return None, wall, out.stderr.strip()
    return json.loads(out.stdout), wall, ""


def peer(script, args):
    t0 = time.perf_counter()
    out = subprocess.run([peer_python, os.path.join(peers, script), *args], capture_output=True,
                         text=True, env=env, cwd=peers)
    wall = time.perf_counter() - t0
    rows = [json.loads(l) for l in out.stdout.splitlines() if l.startswith("{")]
    return rows, wall


def ratio(a, b):
    return f"{a / b:.1f}x" if b > 0 else "-"


with tempfile.TemporaryDirectory() as tmp:
    print(f"one thread each; time limit {time_limit:g} s; k = a = 1, T = 10, mu+ = 1, "
          "mu- = 1.5 (1.6 for N = 5)\n")
    print("## P_M global: crawlopt --method discrete vs the plain big-M MILP (milp_highs.py)\n")
    print("| N | M | crawlopt J_M | status | gap | time s | peer J_M (sim) | peer status | "
          "peer gap | peer time s | peer / crawlopt time |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for case in os.environ["PM_CASES"].split():
        n, big_m = map(int, case.split(":"))
        m = big_m.bit_length() - 1
        r, wall, err = ours([model_file(n, tmp), "--method", "discrete", "--m", str(m),
                             "--time-limit", str(time_limit)])
        rows, pwall = peer("milp_highs.py", ["--N", str(n), "--M", str(big_m), "--mum",
                                             str(mu_backward(n)), "--time_limit",
                                             str(time_limit), "--threads", "1"])
        p = rows[0] if rows else {}
        ours_txt = (f"{r['objective']:.6f} | {r['status']} | {r['certificate']['gap']:.1e} | "
                    f"{wall:.2f}") if r else f"error: {err} | - | - | {wall:.2f}"
        peer_obj = p.get("sim_obj", p.get("obj"))
        peer_txt = (f"{peer_obj:.6f} | {p.get('status')} | {p.get('gap', float('nan')):.1e} | "
                    f"{p.get('time_s', pwall):.2f}") if peer_obj is not None else \
            f"none | {p.get('status')} | - | {pwall:.2f}"
        print(f"| {n} | {big_m} | {ours_txt} | {peer_txt} | "
              f"{ratio(p.get('time_s', pwall), wall)} |", flush=True)

    print("\n## Continuous-time optimum: crawlopt phase gaits (K grown until no gain)\n")
    print("| N | J* (certified among <= K slip phases) | K | stop | time s |")
    print("|---|---|---|---|---|")
    best = {}
    for n in map(int, os.environ["PHASE_NS"].split()):
        r, wall, err = ours([model_file(n, tmp), "--time-limit",
                             os.environ.get("PHASE_TIME_LIMIT", str(time_limit))])
        if r is None:
            print(f"| {n} | error: {err} | - | - | {wall:.2f} |")
            continue
        best[n] = r["objective"]
        print(f"| {n} | {r['objective']:.6f} | {r['certificate']['phases']} | "
              f"{r['phase_growth']['stop']} | {wall:.2f} |", flush=True)

    print(f"\n## P_M locally: crawlopt --method local (start: phase gait) vs CasADi + IPOPT "
          f"(Scholtes, {starts} starts) on the same grid\n")
    print("| N | M | crawlopt local J_M | time s | IPOPT best (sim) | IPOPT median | IPOPT time s | "
          "best continuous J* (phase) | crawlopt / J* | IPOPT / J* | IPOPT / crawlopt time |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for case in os.environ["IPOPT_CASES"].split():
        n, big_m = map(int, case.split(":"))
        m = big_m.bit_length() - 1
        r, wall, err = ours([model_file(n, tmp), "--method", "local", "--m", str(m),
                             "--time-limit", os.environ.get("LOCAL_TIME_LIMIT", "16")])
        rows, pwall = peer("casadi_mpcc.py", ["--N", str(n), "--M", str(big_m), "--mum",
                                              str(mu_backward(n)), "--starts", str(starts)])
        vals = sorted(r2["sim_obj"] for r2 in rows if r2.get("sim_obj") is not None)
        j = best.get(n)
        ours_txt = f"{r['objective']:.6f} | {wall:.2f}" if r else f"error: {err} | {wall:.2f}"
        ipopt_txt = (f"{vals[-1]:.6f} | {vals[len(vals) // 2]:.6f} | {pwall:.1f}" if vals
                     else f"none | - | {pwall:.1f}")
        j_txt = "-" if j is None else f"{j:.6f}"
        ours_rel = f"{r['objective'] / j:.4f}" if (j and r) else "-"
        ipopt_rel = f"{vals[-1] / j:.4f}" if (j and vals) else "-"
        print(f"| {n} | {big_m} | {ours_txt} | {ipopt_txt} | {j_txt} | {ours_rel} | "
              f"{ipopt_rel} | {ratio(pwall, wall)} |", flush=True)
