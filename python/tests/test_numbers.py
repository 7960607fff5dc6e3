"""Numbers through Python: the paper's closed forms, the N = 3 optimum with its certificate,
arrays' shapes and dtypes, round trips with the command line."""

import json
import subprocess

import crawlopt as co
import numpy as np
import pytest


@pytest.mark.parametrize("method", ["exact", "catching_up"])
@pytest.mark.parametrize("amplitude", [0.5, 1.0, 3.0, 7.0])
def test_one_link_sine_displacement_is_the_closed_form(method, amplitude):
    # theory §10: one link, k = 1, mu+ = 1, mu- = 2 on both blocks, L = A sin(2 pi t): the
    # displacement per period is max(0, 2A - 2) (the paper's §4).
    c = co.Crawler(blocks=2, stiffness=1.0, mu_forward=1.0, mu_backward=2.0)
    act = co.Actuation.sine(period=1.0, amplitude=[amplitude])
    sim = co.simulate(c, act, method=method, steps_per_period=4000)
    tol = 1e-12 if method == "exact" else 2e-3
    assert sim.displacement_per_period == pytest.approx(max(0.0, 2 * amplitude - 2), abs=tol)


def test_one_link_gait_optimum_is_the_closed_form():
    # theory §10: J* = (a T - 2 w) / (2 k) = (10 - 4) / 2 = 3 for examples/one_link_gait.toml.
    m = co.load("examples/one_link_gait.toml")
    a = m.crawler.analyze()
    assert a.one_link["width"] == pytest.approx(2.0)  # w = 2 (the file's comment)
    r = co.optimize(m.crawler, m.gait_problem)
    assert r.objective == pytest.approx(3.0, abs=1e-8)
    assert r.status == "optimal_among_k_phases" and r.certificate["phases"] >= 2


def test_three_blocks_optimum_with_its_certificate():
    m = co.load("examples/three_blocks_gait.toml")
    r = co.optimize(m.crawler, m.gait_problem, certify=True)
    assert r.objective == pytest.approx(2.6, abs=1e-8)
    assert r.certificate["kind"] == "global_k_phases"
    assert r.certificate["gap"] <= 1e-6
    assert r.necessary_conditions["verdict"] in ("holds", "degenerate")
    # The phase growth: J_K = 0 up to K = 2, 13/6 at K = 3, 2.6 from K = 4 (tests/gait_costs.rs).
    table = r.phase_growth["table"]
    assert [row["phases"] for row in table][:4] == [1, 2, 3, 4]
    assert table[2]["objective"] == pytest.approx(13 / 6, abs=1e-8)
    assert r.displacement_per_period == pytest.approx(2.6, abs=1e-8)


def test_same_problem_built_in_python_and_read_from_the_file():
    c = co.Crawler(blocks=3, stiffness=1.0, mu_forward=1.0, mu_backward=1.5)
    prob = co.GaitProblem(period=10, max_actuator_speed=1.0)
    r = co.optimize(c, prob, method="phase", phases=3)
    assert r.objective == pytest.approx(13 / 6, abs=1e-8)
    # The cost is charged: with c = 0.05 the optimum among 4 slip phases still moves (at
    # c = 0.5 it stays idle, the MILP's bound being 0, and charges nothing).
    quad = co.optimize(
        c, co.GaitProblem(period=10, cost=co.Quadratic(0.05)), method="phase", phases=4
    )
    assert quad.objective < 2.6
    assert quad.actuation_cost > 0
    assert quad.objective == pytest.approx(
        quad.displacement_per_period - quad.actuation_cost, abs=1e-12
    )


def test_arrays_have_their_shapes_and_dtypes():
    m = co.load("examples/three_blocks_sine.toml")
    sim = co.simulate(m.crawler, m.actuation, periods=2)
    assert sim.displacement_per_period == pytest.approx(1.914213562, abs=1e-9)
    n = len(sim.t)
    assert sim.t.dtype == np.float64 and sim.t.shape == (n,)
    assert sim.x.shape == (n, 2) and sim.X.shape == (n, 3) and sim.y.shape == (n,)
    assert sim.slip.dtype == np.int8 and sim.slip.shape == (n, 3)
    for a in (sim.t, sim.x, sim.X, sim.y, sim.slip):
        assert a.flags["C_CONTIGUOUS"]
    # The barycentre is the mean of the blocks; two periods recorded.
    assert np.allclose(sim.y, sim.X.mean(axis=1))
    assert sim.t[-1] - sim.t[0] == pytest.approx(2.0)
    r = co.optimize(
        co.Crawler(blocks=3, mu_backward=1.5), co.GaitProblem(period=10), method="phase", phases=3
    )
    g = r.gait
    k = len(g.u)
    assert g.t.shape == (k + 1,) and g.u.shape == (k, 2) and g.slip.shape == (k, 3)
    assert g.slip.dtype == np.int8 and g.L.dtype == np.float64


def _optimize_json(cli, path):
    """``crawlopt optimize PATH --json``: the result document's text."""
    return subprocess.run(
        [cli, "optimize", path, "--json"], check=True, capture_output=True, text=True
    ).stdout


def test_results_round_trip_with_the_command_line(cli, tmp_path):
    out = _optimize_json(cli, "examples/three_blocks_gait.toml")
    r = co.GaitResult.from_json(out)
    assert r.objective == pytest.approx(2.6, abs=1e-8)
    # Python writes the same document, byte for byte.
    assert r.to_json() == out.strip()
    path = tmp_path / "r.json"
    path.write_text(r.to_json())
    cert = json.loads(
        subprocess.run(
            [cli, "certify", str(path), "--json"], check=True, capture_output=True, text=True
        ).stdout
    )
    mine = r.certify()
    assert cert["verdict"] == mine["verdict"]
    assert cert["objective"] == pytest.approx(mine["objective"], abs=1e-12)
    # And a result computed in Python is read by the CLI's report.
    html = tmp_path / "r.html"
    subprocess.run([cli, "report", str(path), "-o", str(html)], check=True, capture_output=True)
    assert "2.6" in html.read_text()


def test_version_1_results_read_as_the_current_version(cli, tmp_path):
    # A result of version 1 (the gait under "gait", no "kind"; the crawler, its gait problem
    # and the solution's numbers at the top level, as up to version 3) reads to the same
    # result, with the same certificate; errors on it say that its gait was read as the
    # solution.
    out = _optimize_json(cli, "examples/three_blocks_gait.toml")
    doc = json.loads(out)
    assert doc["version"] == 4 and "solution" in doc and "gait" not in doc
    gait = dict(doc["solution"])
    numbers = ("m", "displacement_per_period", "actuation_cost", "local", "polish")
    moved = {k: gait.pop(k) for k in numbers if k in gait}
    old = dict(doc, version=1, gait=gait, **moved)
    old.update(crawler=doc["problem"]["crawler"], problem=doc["problem"]["gait"])
    old["verified_displacement"] = moved["displacement_per_period"]
    del old["solution"], old["kind"]
    path = tmp_path / "old.json"
    path.write_text(json.dumps(old))
    r1, r2 = co.read_result(path), co.GaitResult.from_json(out)
    assert r1.to_json() == r2.to_json()
    assert r1.gait.durations == pytest.approx(r2.gait.durations, abs=0)
    assert r1.certify()["verdict"] == r2.certify()["verdict"]
    old["gait"] = dict(old["gait"], states=old["gait"]["states"][:-1])
    with pytest.raises(ValueError, match=r"version 1, its gait read as solution\): solution"):
        co.GaitResult.from_json(json.dumps(old))


def test_figures_and_report(tmp_path):
    m = co.load("examples/three_blocks_gait.toml")
    r = co.optimize(m.crawler, m.gait_problem, method="phase", phases=4)
    figs = r.figures(adjoint=True)
    assert {"spacetime", "actuation", "adjoint"} <= set(figs)
    assert (
        figs["spacetime"]._repr_svg_().lstrip().startswith("<svg")
        or "<svg" in figs["spacetime"].svg[:200]
    )
    html = r.report(tmp_path / "gait.html")
    assert (tmp_path / "gait.html").read_text() == html
    assert "<script" in html and "2.6" in html
    assert "2.6" in r._repr_html_() and "<svg" in r._repr_html_()
    assert len(repr(r).splitlines()) == 1


def test_progress_events_arrive_in_order():
    events = []
    m = co.load("examples/three_blocks_gait.toml")
    co.optimize(m.crawler, m.gait_problem, progress=events.append)
    kinds = [e["kind"] for e in events]
    assert kinds[0] == "stage"
    phases = [e["K"] for e in events if e["kind"] == "phase"]
    assert phases == list(range(1, len(phases) + 1))
    assert all(a["seconds"] <= b["seconds"] for a, b in zip(events, events[1:]))
    assert any(e["kind"] == "milp" and e["incumbent"] is not None for e in events)


def test_tables_as_pandas():
    pd = pytest.importorskip("pandas")
    m = co.load("examples/three_blocks_sine.toml")
    sim = co.simulate(m.crawler, m.actuation, periods=1)
    df = sim.to_pandas()
    assert isinstance(df, pd.DataFrame)
    assert list(df.columns[:4]) == ["t", "y", "x_1", "x_2"]
    assert len(df) == len(sim.t) and np.allclose(df["X_3"], sim.X[:, 2])
    g = co.load("examples/three_blocks_gait.toml")
    r = co.optimize(g.crawler, g.gait_problem)
    growth = r.phase_growth_table()
    assert growth["objective"].iloc[-1] == pytest.approx(2.6, abs=1e-8)
    pieces = r.to_pandas()
    assert len(pieces) == len(r.gait.u)
    assert np.allclose(pieces["t_end"] - pieces["t_start"], r.gait.durations)
    table = co.optimize(
        co.load("examples/one_link_gait.toml").crawler,
        co.load("examples/one_link_gait.toml").gait_problem,
        method="discrete",
        m=3,
        convergence=True,
    ).convergence_table()
    assert list(table["m"]) == [1, 2, 3]
    # J_m approaches the continuous optimum 3 from below.
    assert (table["objective"] <= 3.0 + 1e-9).all()


def test_the_upper_bound_over_all_gaits_for_one_link():
    # N = 2, mu+ = 1, mu- = 2, k = a = 1, T = 10: J* = 3 (theory §10); the storage-function bound
    # on an R x R grid is J* + 2h with h = w / R = 2 / R (measured exactly: README).
    c = co.Crawler(blocks=2, mu_forward=1.0, mu_backward=2.0)
    p = co.GaitProblem(period=10, max_actuator_speed=1.0)
    r = co.optimize(c, p, bound={"resolution": 16, "box_resolution": 16})
    ub = r.certificate["upper_bound"]
    assert r.objective == pytest.approx(3.0, abs=1e-9)
    assert ub["value"] == pytest.approx(3.25, abs=1e-7)
    assert ub["method"] == "pl-storage" and ub["resolution"] == 16
    assert "upper bound over all periodic gaits" in str(r)
    assert 'id="upper-bound"' in r.report()
    back = co.GaitResult.from_json(r.to_json())
    assert back.certificate["upper_bound"]["value"] == ub["value"]
    with pytest.raises(co.InputError) as e:
        co.optimize(c, p, bound={"grid": 4})
    assert e.value.field == "bound.grid"
    with pytest.raises(co.InputError) as e:
        co.optimize(c, p, bound={"resolution": 0})
    assert e.value.field == "bound.resolution"
    # Quadratic cost c = 0.2 (optimum at the rate bound, J* = 2): the bound is J* + 2h plus
    # T c a^2 / (2 M^2) from M tangents per link (tests/upper_bound.rs, README).
    q = co.GaitProblem(period=10, max_actuator_speed=1.0, cost=co.Quadratic(0.2))
    r = co.optimize(c, q, bound={"resolution": 16, "box_resolution": 16, "cost_tangents": 4})
    assert r.objective == pytest.approx(2.0, abs=1e-6)
    assert r.certificate["upper_bound"]["value"] == pytest.approx(2.3125, abs=1e-6)
    assert r.certificate["upper_bound"]["cost_tangents"] == 4


def test_chain_method_is_at_least_the_alternating_triangle_wave():
    # Uniform chain of 10 blocks (k = a = 1, T = 10, mu+ = 1, mu- = 1.3): the alternating
    # triangle wave moves 4 - 1/(N - 1); the chain method starts from it and never returns less.
    c = co.Crawler(blocks=10, mu_backward=1.3)
    r = co.optimize(c, co.GaitProblem(period=10), method="chain", time_limit=5)
    assert r.objective >= 4 - 1 / 9 - 1e-9
    assert r.structured["origin"].startswith(("structured: ", "chain pattern search"))
