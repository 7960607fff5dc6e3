"""Issue 28: objects that behave as Python objects do. They pickle, deep-copy and compare by
value (so they go to multiprocessing), scalars broadcast as in the model file, a travelling
wave, models written back as files, a simulation that did not converge says so, general
problems from arrays, typed results."""

import copy
import json
import multiprocessing
import pickle
import subprocess
import warnings

import crawlopt as co
import numpy as np
import pytest


def _round_trips(obj):
    """pickle and deepcopy give an equal object (of the same type)."""
    for again in (pickle.loads(pickle.dumps(obj)), copy.deepcopy(obj), copy.copy(obj)):
        assert type(again) is type(obj)
        assert again == obj
        assert not (again != obj)


def test_models_pickle_deep_copy_and_compare_by_value():
    c = co.Crawler(blocks=3, stiffness=[1.0, 2.0], mu_forward=1.0, mu_backward=3.0)
    assert c == co.Crawler(blocks=3, stiffness=[1.0, 2.0], mu_forward=[1.0] * 3, mu_backward=3.0)
    assert hash(c) == hash(co.Crawler(3, [1.0, 2.0], 1.0, 3.0))
    assert c != co.Crawler(blocks=3, stiffness=[1.0, 2.5], mu_forward=1.0, mu_backward=3.0)
    assert len({c, copy.deepcopy(c)}) == 1
    actuations = [
        co.Actuation.sine(1.0, [2.0, 2.0], phase_deg=[0.0, 90.0]),
        co.Actuation.sine(1.0, 2.0),  # for any crawler
        co.Actuation.triangle(2.0, 1.0, links=4),
        co.Actuation.piecewise_linear(1.0, [0.0, 0.5], [[0.0, 1.0], 2.0]),
        co.Actuation.travelling_wave(5, amplitude=2.0, lag_deg=45.0),
    ]
    for a in actuations:
        _round_trips(a)
    assert actuations[0] != actuations[1] and actuations[0] != 3
    with pytest.raises(TypeError):
        hash(actuations[0])
    p = co.GaitProblem(period=10.0, max_actuator_speed=[1.0, 0.5], cost=co.Quadratic(0.1))
    _round_trips(p)
    assert p != co.GaitProblem(period=10.0, max_actuator_speed=[1.0, 0.5])
    m = co.load("examples/three_blocks_gait.toml")
    _round_trips(m)
    _round_trips(m.gait_problem)
    assert m == co.load("examples/three_blocks_gait.toml")
    assert m != co.load("examples/three_blocks_sine.toml")
    g = co.load("examples/general_one_link.toml")
    _round_trips(g)
    assert g != co.load("examples/general_drift.toml")


def test_results_pickle_deep_copy_and_compare_by_value():
    m = co.load("examples/three_blocks_sine.toml")
    sim = co.simulate(m.crawler, m.actuation)
    _round_trips(sim)
    assert pickle.loads(pickle.dumps(sim)).figures()  # still knows its crawler
    one = co.load("examples/one_link_gait.toml")
    r = co.optimize(one.crawler, one.gait_problem, method="phase", phases=2, certify=True)
    _round_trips(r)
    assert isinstance(r.necessary_conditions, co.NecessaryConditions)
    _round_trips(r.necessary_conditions)
    other = co.optimize(one.crawler, one.gait_problem, method="phase", phases=2)
    assert r != other  # no certificate
    g = co.load("examples/general_one_link.toml")
    gr = g.optimize(m=2, certify=True)
    _round_trips(gr)
    _round_trips(g.simulate())


def _displacement(args):
    crawler, actuation = args
    return co.simulate(crawler, actuation).displacement_per_period


def test_crawlers_go_to_a_process_pool():
    crawlers = [co.Crawler(blocks=2, mu_forward=1.0, mu_backward=2.0) for _ in range(2)]
    act = co.Actuation.sine(period=1.0, amplitude=[3.0])
    with multiprocessing.get_context("spawn").Pool(2) as pool:
        got = pool.map(_displacement, [(c, act) for c in crawlers])
    # max(0, 2A - 2) for one link (theory §10), as in this process.
    assert got == pytest.approx([4.0, 4.0], abs=1e-9)


def test_a_number_stands_for_every_link_as_in_the_file(tmp_path):
    """Actuation.sine(period=1, amplitude=2.0, phase_deg=[29 values]) failed ("must have 1
    entries") where the file form broadcasts the number."""
    phases = [12.5 * k for k in range(29)]
    a = co.Actuation.sine(period=1, amplitude=2.0, phase_deg=phases)
    assert a.links == 29
    f = tmp_path / "m.toml"
    f.write_text(
        "[crawler]\nblocks = 30\nstiffness = 1\nmu_forward = 1\nmu_backward = 3\n"
        f'[actuation]\nkind = "sine"\nperiod = 1\namplitude = 2.0\nphase_deg = {phases}\n'
    )
    assert co.load(str(f)).actuation == a
    # All numbers: the actuation fits any crawler, as the file's section does.
    b = co.Actuation.sine(period=1.0, amplitude=2.0, phase_deg=30.0)
    assert b.links is None
    assert b.for_links(3) == co.Actuation.sine(1.0, [2.0] * 3, phase_deg=[30.0] * 3)
    c = co.Crawler(blocks=4, mu_forward=1.0, mu_backward=2.5)
    assert co.simulate(c, b) == co.simulate(c, b.for_links(3))
    # Lists of different lengths: refused by the library, naming the field.
    with pytest.raises(co.InputError) as e:
        co.Actuation.sine(1.0, [1.0, 2.0], phase_deg=[0.0, 1.0, 2.0])
    assert e.value.field == "actuation.phase_deg"
    with pytest.raises(co.InputError) as e:
        co.Crawler(blocks=3, stiffness=[1.0, 2.0, 3.0])
    assert e.value.field == "crawler.stiffness"


def test_a_travelling_wave_lags_each_link_behind_its_neighbour():
    w = co.Actuation.travelling_wave(4, period=2.0, amplitude=1.5, lag_deg=45.0)
    assert w == co.Actuation.sine(2.0, 1.5, phase_deg=[0.0, 45.0, 90.0, 135.0])
    t = np.array([0.0, 0.3, 1.1])
    now, later = w(t), w(t + 2.0 * 45.0 / 360.0)
    assert np.allclose(later[:, 1:], now[:, :-1], atol=1e-12)
    # Defaults: one wavelength along the body, first to last; the other direction.
    assert co.Actuation.travelling_wave(4) == co.Actuation.sine(1.0, 1.0, [0, 90, 180, 270])
    back = co.Actuation.travelling_wave(3, wavelength=6.0, direction="last_to_first")
    assert back == co.Actuation.sine(1.0, 1.0, [120.0, 60.0, 0.0])
    tri = co.Actuation.travelling_wave(2, waveform="triangle", mean=1.0)
    assert tri.kind == "triangle"
    for kwargs, field in [
        (dict(lag_deg=10.0, wavelength=2.0), "actuation.wavelength"),
        (dict(wavelength=0.0), "actuation.wavelength"),
        (dict(direction="up"), "actuation.direction"),
        (dict(waveform="square"), "actuation.waveform"),
        (dict(amplitude=-1.0), "actuation.amplitude[1]"),
    ]:
        with pytest.raises(co.InputError) as e:
            co.Actuation.travelling_wave(3, **kwargs)
        assert e.value.field == field, str(e.value)


def test_a_model_built_in_code_is_saved_and_read_back(tmp_path, cli):
    c = co.Crawler(blocks=3, stiffness=[1.0, 0.1 + 0.2], mu_forward=1.0, mu_backward=3.0)
    model = co.Model(
        c,
        actuation=co.Actuation.travelling_wave(2, amplitude=2.0, lag_deg=1.0 / 3.0),
        gait_problem=co.GaitProblem(10.0, [1.0, 2.0 / 3.0], co.Quadratic(0.1), 5.0),
        initial_state=[0.1, -0.2],
    )
    path = tmp_path / "model.toml"
    model.save(str(path))
    back = co.load(str(path))
    assert back == model
    assert back.to_toml() == model.to_toml() == path.read_text()
    # The command line reads it, and simulates what Python simulates.
    out = subprocess.run(
        [cli, "simulate", str(path), "--json"], capture_output=True, text=True, check=True
    )
    d = json.loads(out.stdout)["displacement_per_period"]
    assert d == co.simulate(c, model.actuation).displacement_per_period
    # A section of a loaded file: unchanged; an actuation alone writes its section.
    m = co.load("examples/piecewise_linear.toml")
    assert co.load(_saved(m, tmp_path)) == m
    assert m.actuation.to_toml().startswith("[actuation]\n")
    # A model whose actuation does not fit its crawler is not written.
    bad = co.Model(c, actuation=co.Actuation.sine(1.0, [1.0, 1.0, 1.0]))
    with pytest.raises(co.InputError) as e:
        bad.to_toml()
    assert e.value.field.startswith("actuation")


def _saved(model, tmp_path) -> str:
    p = tmp_path / "again.toml"
    model.save(str(p))
    return str(p)


def test_a_simulation_that_does_not_converge_cannot_be_missed():
    c = co.Crawler(blocks=6, mu_forward=1.0, mu_backward=3.0)
    a = co.Actuation.travelling_wave(5, amplitude=2.0, lag_deg=45.0)
    with pytest.warns(co.NotConvergedWarning, match="not reached within 2 periods"):
        s = co.simulate(c, a, max_periods=2, accelerate=False)
    assert s.status == "not_converged" and s.displacement_per_period is None
    assert "not_converged" in repr(s) and "NOT reached" in repr(s)
    assert "not reached" in s._repr_html_()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ok = co.simulate(c, a)
    assert ok.status == "converged" and "status='converged'" in repr(ok)
    g = co.load("examples/general_drift.toml")
    with pytest.warns(co.NotConvergedWarning, match="not reached within 1 periods"):
        gs = g.simulate(max_periods=1, method="catching_up")
    assert gs.status == "not_converged" and gs.objective is None
    assert "not_converged" in repr(gs) and "not reached" in repr(gs)


def _one_link_arrays(**change):
    """The paper's §4 one-link problem (examples/general_one_link.toml) as arrays."""
    kw = dict(
        normals=np.array([[1.0], [-1.0]]),
        offsets=np.array([1.0, 1.0]),
        B=np.eye(1),
        lower=[-1.0],
        upper=[1.0],
        zero_mean=True,
        face_weights=np.array([0.5, 0.5]),
        period=10.0,
        input=dict(kind="piecewise_constant", times=[0.0, 5.0], values=[[1.0], [-1.0]]),
    )
    kw.update(change)
    return co.GeneralProblem(**kw)


def _keywords(sections: dict) -> dict:
    """A problem's sections as the constructor's keywords (the file's keys)."""
    kw = {}
    for name in ("sweeping_process", "dynamics", "control", "objective", "problem"):
        kw.update(sections.get(name, {}))
    if "input" in sections:
        kw["input"] = sections["input"]
    return kw


def test_a_general_problem_from_arrays(tmp_path, cli):
    g = _one_link_arrays()
    assert g == co.load("examples/general_one_link.toml")
    assert repr(g) == "GeneralProblem(faces=2, states=1, controls=1, period=10)"
    assert g.to_dict()["objective"] == {"face_weights": [0.5, 0.5]}
    assert co.GeneralProblem(**_keywords(g.to_dict())) == g
    path = tmp_path / "general.toml"
    g.save(str(path))
    assert co.load(str(path)) == g
    out = subprocess.run(
        [cli, "simulate", str(path), "--json"], capture_output=True, text=True, check=True
    )
    assert json.loads(out.stdout)["simulation"]["objective"] == pytest.approx(3.0, abs=1e-12)
    sim = g.simulate()
    assert isinstance(sim, co.GeneralSimulation) and sim.objective == pytest.approx(3.0)
    # J* = (T - 2 (b - a)) / 2 = 3 (theory §10), with a quadratic cost c: less.
    r = _one_link_arrays(cost=0.1).optimize(m=2)
    assert r.objective < 3.0
    assert _one_link_arrays(cost=co.Quadratic(0.1)) == _one_link_arrays(cost=0.1)
    assert _one_link_arrays(cost=[[0.1]]) != _one_link_arrays(cost=0.1)
    priced = _one_link_arrays(cost=[[0.1]])
    assert co.GeneralProblem(**_keywords(priced.to_dict())) == priced
    # Validation is the library's, naming the file's field.
    for change, field in [
        (dict(B=[[1.0, 2.0]]), "control.lower"),
        (dict(offsets=[1.0]), "sweeping_process.offsets"),
        (dict(B=[1.0]), "dynamics.B"),
        (dict(cost=-1.0), "objective.cost.weight"),
    ]:
        with pytest.raises(co.InputError) as e:
            _one_link_arrays(**change)
        assert e.value.field == field, str(e.value)


def test_typed_results_of_both_kinds():
    g = co.load("examples/general_one_link.toml")
    r = g.optimize(m=3, certify=True)
    assert isinstance(r, co.GeneralResult)
    assert r.objective == pytest.approx(3.0, abs=1e-9) and r.status == "optimal"
    assert r["objective"] == r.objective  # the dict form still reads
    assert r.u.shape == (8, 1) and r.reactions.shape == (8, 2)
    assert r.u is r.controls and r.x is r.states and r.states.shape == (9, 1)
    nc = r.necessary_conditions
    assert isinstance(nc, co.NecessaryConditions) and nc.verdict == "holds"
    assert "GeneralResult(method='discrete'" in repr(r) and "holds" in repr(r)
    d = r.to_dict()
    assert d["necessary_conditions"]["verdict"] == "holds"
    json.dumps({k: v for k, v in d.items() if k != "solution"})
    pieces = r.to_pandas()
    assert len(pieces) == 8 and list(pieces.columns[:3]) == ["t_start", "t_end", "u_1"]
    assert np.allclose(pieces["u_1"], r.u[:, 0])
    assert len(nc.to_pandas()) == len(nc.conditions)
    phase = g.optimize(method="phase")
    assert phase.to_pandas()["duration"].sum() == pytest.approx(10.0)
    sim = g.simulate()
    table = sim.to_pandas()
    assert list(table.columns) == ["t", "x_1", "u_1", "lambda_1", "lambda_2"]
    assert np.isnan(table["u_1"].iloc[0]) and len(table) == len(sim.t)
    one = co.load("examples/one_link_gait.toml")
    cert = co.optimize(one.crawler, one.gait_problem, method="phase", phases=2).certify()
    assert isinstance(cert, co.NecessaryConditions) and cert["verdict"] == cert.verdict


def test_a_file_of_either_kind_runs_its_jobs_by_the_same_methods():
    # Whatever load returns takes analyze(), simulate() and optimize(): a crawler's model
    # answers as the free functions do, and its general form (the same three blocks as (P))
    # reaches the same J by (P)'s own phase method.
    m = co.load("examples/three_blocks_gait.toml")
    g = co.load("examples/general_three_blocks.toml")
    assert m.analyze().to_dict() == m.crawler.analyze().to_dict()
    assert g.analyze().check("structure")["detail"].startswith("a chain")
    a = m.optimize(method="phase", phases=2)
    b = co.optimize(m.crawler, m.gait_problem, method="phase", phases=2)
    assert isinstance(a, co.GaitResult) and a == b
    general = g.optimize(method="phase", phases=2)
    assert isinstance(general, co.GeneralResult)
    assert general.objective == pytest.approx(a.objective, rel=1e-9)
    sine = co.load("examples/three_blocks_sine.toml")
    s = sine.simulate(periods=1)
    t = co.simulate(sine.crawler, sine.actuation, periods=1, initial_state=sine.initial_state)
    assert s.displacement_per_period == t.displacement_per_period
    assert np.array_equal(s.x, t.x)
    # A model lacking the part a job needs is refused naming it, as the command line does.
    with pytest.raises(co.InputError) as e:
        m.simulate()
    assert e.value.field == "actuation"
    with pytest.raises(co.InputError) as e:
        sine.optimize()
    assert e.value.field == "gait_problem"


def test_pandas_and_matplotlib_are_optional(monkeypatch):
    import sys

    g = co.load("examples/general_one_link.toml")
    r = g.optimize(m=2)
    monkeypatch.setitem(sys.modules, "pandas", None)
    with pytest.raises(ImportError, match="to_pandas\\(\\) needs pandas.*pip install pandas"):
        r.to_pandas()
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    monkeypatch.setitem(sys.modules, "matplotlib.pyplot", None)
    with pytest.raises(ImportError, match="plot\\(\\) needs matplotlib.*pip install matplotlib"):
        r.plot()
    assert "<table>" in r._repr_html_()  # the numbers, without the figure


def _png(fig) -> np.ndarray:
    import io

    import matplotlib.pyplot as plt

    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=50)
    plt.close(fig)
    buf.seek(0)
    return plt.imread(buf)


def test_plots_and_their_html_form():
    pytest.importorskip("matplotlib")
    import matplotlib

    matplotlib.use("Agg")
    m = co.load("examples/three_blocks_sine.toml")
    sim = co.simulate(m.crawler, m.actuation)
    fig = sim.plot()
    top, bottom = fig.axes
    assert len(top.lines) == 4 and len(bottom.lines) == 2  # 3 blocks + barycentre; 2 links
    assert np.allclose(top.lines[3].get_ydata(), sim.y)
    img = _png(fig)
    assert img.shape[:2] == (250, 350)  # 7 x 5 inches at 50 dpi
    assert img[..., :3].std() > 0.05  # drawn, not blank
    html = sim._repr_html_()
    assert html.count("<svg") == 2 and "displacement per period" in html
    assert set(sim.figures()) == {"actuation", "spacetime", "polytope"}
    one = co.load("examples/one_link_gait.toml")
    r = co.optimize(one.crawler, one.gait_problem, method="phase", phases=2)
    fig = r.plot()
    assert len(fig.axes) == 2 and len(fig.axes[0].lines) == 1
    assert np.allclose(fig.axes[0].lines[0].get_ydata(), r.gait.L[:, 0])
    assert _png(fig)[..., :3].std() > 0.05
    html = r._repr_html_()
    assert html.count("<svg") == 2 and "objective J" in html
    g = co.load("examples/general_one_link.toml")
    for res in (g.simulate(), g.optimize(m=2)):
        fig = res.plot()
        assert len(fig.axes) == 2 and _png(fig)[..., :3].std() > 0.05
        assert "<svg" in res._repr_html_() and "<table>" in res._repr_html_()


def test_the_report_of_a_certified_gait_has_its_certificate(tmp_path):
    one = co.load("examples/one_link_gait.toml")
    r = co.optimize(one.crawler, one.gait_problem, method="phase", phases=2, certify=True)
    page = r.report(str(tmp_path / "r.html"))
    assert page == (tmp_path / "r.html").read_text()
    assert '<h2 id="certificate">' in page and 'id="fig-adjoint"' in page
    assert f'<b id="verdict">{r.necessary_conditions.verdict}</b>' in page
    assert "<code>crawlopt.GaitResult.report (Python)</code>" in page
    plain = co.optimize(one.crawler, one.gait_problem, method="phase", phases=2).report()
    assert 'id="certificate"' not in plain
