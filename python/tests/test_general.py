"""General problem files (``[sweeping_process]``, the paper's §2 problem (P)) from Python:
``crawlopt.load`` gives a GeneralProblem whose analysis, simulation and P_m (global and local)
and exact phase gaits are the library's, with the closed form of the §4 one-link problem."""

import json
import pickle
import re
from pathlib import Path

import crawlopt as co
import numpy as np
import pytest
from conftest import example

# The one-link problem of §4 in general form: C = [a, b] = [-1, 1], g = u, U = [-1, 1],
# f1 = |eta| / 2, T = 10: J* = (T - 2 (b - a)) / 2 = 3.
ONE_LINK = example("general_one_link.toml")
J_STAR = (10.0 - 2 * (1.0 - (-1.0))) / 2


def test_load_gives_a_general_problem_with_its_analysis():
    p = co.load(ONE_LINK)
    assert isinstance(p, co.GeneralProblem)
    a = p.analyze()
    assert a["kind"] == "general" and a["failure"] is None
    assert all(c["status"] != "fail" for c in a["checks"])
    assert a["geometry"]["chebyshev_radius"] == pytest.approx(1.0)
    # A crawler file still gives a Model.
    assert isinstance(co.load(example("three_blocks_gait.toml")), co.Model)


def test_the_analysis_is_a_typed_document():
    """``analyze()`` gives a ``GeneralAnalysis``, as a crawler's gives an ``Analysis``: its
    fields as attributes and as items, ``well_posed``, a check by name (the chain recognised
    in the three-block crawler written as (P); an unknown name is a KeyError naming the checks
    there are), and it pickles to an equal document."""
    a = co.load(ONE_LINK).analyze()
    assert isinstance(a, co.GeneralAnalysis)
    assert a.well_posed and a.failure is None and a["failure"] is None
    assert a.geometry["chebyshev_radius"] == pytest.approx(1.0)
    assert a.check("C is bounded")["status"] == "info"
    three = co.load(ONE_LINK.replace("general_one_link", "general_three_blocks")).analyze()
    assert three.check("structure")["detail"].startswith("a chain: the gait problem of a crawler")
    with pytest.raises(KeyError, match="the checks are"):
        three.check("no such check")
    assert pickle.loads(pickle.dumps(three)) == three
    assert "well_posed=True" in repr(three) and "<table" in three._repr_html_()
    # A repeated face makes the face weights ill defined at the vertex it shares.
    bad = co.GeneralProblem(
        normals=[[1.0], [-1.0], [1.0]],
        offsets=[1.0, 1.0, 1.0],
        B=[[1.0]],
        lower=[-1.0],
        upper=[1.0],
        face_weights=[0.5, 0.5, 0.5],
        period=10.0,
    ).analyze()
    assert not bad.well_posed
    assert bad.failure.startswith("objective.face_weights: are not well defined")
    assert bad.check("face weights well defined")["status"] == "fail"


def test_simulate_and_optimize_reach_the_closed_form():
    p = co.load(ONE_LINK)
    s = p.simulate()
    sim = s["simulation"]
    assert s["method"] == "exact"
    assert sim["objective"] == pytest.approx(J_STAR, abs=1e-9)
    assert isinstance(sim["x"], np.ndarray) and sim["x"].shape[1] == 1
    c = p.simulate(method="catching_up", steps_per_period=64)["simulation"]
    assert c["objective"] == pytest.approx(J_STAR, abs=1e-9)
    assert c["lambda"].shape == (64, 2) and c["u"].shape == (64, 1)

    g = p.optimize(m=2)
    assert g["method"] == "discrete"
    assert g["objective"] == pytest.approx(J_STAR, abs=1e-7)
    assert g["status"] == "optimal"
    assert g["solution"]["controls"].shape == (4, 1)
    # Theorem 2.2's necessary conditions on the P_3 optimum (tests/general_certify.rs checks
    # them against the crawler certificate of the same problem).
    nc = p.optimize(m=3, certify=True)["necessary_conditions"]
    assert nc["verdict"] == "holds", nc["reason"]
    assert nc["objective"] == pytest.approx(J_STAR, abs=1e-7)

    events = []
    loc = p.optimize(m=5, method="local", shifts=2, progress=events.append)
    sol = loc["solution"]
    assert loc["method"] == "local" and loc["starts_tried"] == 2
    assert loc["objective"] == pytest.approx(J_STAR, abs=1e-7)
    assert sol["stop"] == "stationary"
    assert sol["states"].shape == (33, 1) and abs(sol["controls"].sum()) < 1e-9
    assert [e["kind"] for e in events] == ["stage", "stage"]

    # Exact continuous-time gaits (A = 0), in the general formulation (K phases, no free
    # transition): J* with 4 phases (free rise, slide on b, free fall, slide on a), none with 3.
    ph = p.optimize(method="phase", formulation="general")
    sol = ph["solution"]
    assert ph["method"] == "phase" and sol["max_phases"] == 4
    assert ph["objective"] == pytest.approx(J_STAR, abs=1e-7)
    assert ph["status"] == "optimal_among_k_phases"
    assert sol["durations"].sum() == pytest.approx(10.0, abs=1e-9)
    assert sol["states"].shape == (5, 1) and sol["controls"].shape == (4, 1)
    assert sum(1 for h in sol["held"] if h) == 2
    assert p.optimize(method="phase", formulation="general", max_phases=3)[
        "objective"
    ] == pytest.approx(0.0, abs=1e-9)
    # K grown as for crawlers: one row per K, J_K = 0 below 4; a progress event per K; a
    # plateau ends the growth after `patience` K, claimed for the last K; a fixed K, no table.
    events = []
    grown = p.optimize(
        method="phase", formulation="general", max_phases=8, patience=1, progress=events.append
    )
    rows = grown["phase_growth"]["table"]
    assert [r["phases"] for r in rows] == [1, 2, 3, 4, 5]
    assert [r["objective"] for r in rows] == pytest.approx([0, 0, 0, J_STAR, J_STAR], abs=1e-7)
    assert grown["phase_growth"]["stop"] == "no_gain"
    assert grown["certificate"]["phases"] == 5
    assert [e["K"] for e in events if e["kind"] == "phase"] == [1, 2, 3, 4, 5]
    # P_1..P_m tabulated (the crawler's --convergence), J_m = J* on every grid.
    table = p.optimize(m=3, convergence=True)["convergence"]
    assert [r["m"] for r in table] == [1, 2, 3]
    assert [r["objective"] for r in table] == pytest.approx([J_STAR] * 3, abs=1e-7)
    fixed = p.optimize(method="phase", formulation="general", phases=4)
    assert "phase_growth" not in fixed.keys()
    assert fixed["objective"] == pytest.approx(J_STAR, abs=1e-7)


def test_bad_arguments_raise_input_errors_naming_the_field():
    p = co.load(ONE_LINK)
    cases = [
        (lambda: p.optimize(m=11), "m"),
        (lambda: p.optimize(m=15, method="local"), "m"),
        (lambda: p.optimize(method="sequence"), "method"),
        (lambda: p.optimize(method="phase", max_phases=0), "max_phases"),
        (lambda: p.optimize(method="phase", m=3), "m"),
        (lambda: p.optimize(max_phases=4), "max_phases"),
        # The file's [input] starts the local method: no phase gait for max_phases to bound.
        (lambda: p.optimize(method="local", max_phases=2), "max_phases"),
        (lambda: p.optimize(phases=4), "phases"),
        (lambda: p.optimize(method="local", convergence=True), "convergence"),
        (lambda: p.optimize(method="phase", phases=0), "phases"),
        (lambda: p.optimize(method="phase", patience=0), "patience"),
        (lambda: p.optimize(shifts=2), "shifts"),
        (lambda: p.optimize(method="local", shifts=0), "shifts"),
        (lambda: p.optimize(time_limit=-1.0), "time_limit"),
        (lambda: p.simulate(method="rk4"), "method"),
        (lambda: p.simulate(method="catching_up", steps_per_period=0), "steps_per_period"),
        # The exact method (the default here, A = 0) is held to the same settings.
        (lambda: p.simulate(steps_per_period=0), "steps_per_period"),
        (lambda: p.simulate(max_periods=0), "max_periods"),
    ]
    for call, field in cases:
        with pytest.raises(co.InputError) as e:
            call()
        assert e.value.field == field, str(e.value)
    with pytest.raises(co.InputError) as e:
        co.load(example("general_drift.toml")).optimize(method="local")
    assert e.value.field == "objective.cost"


def test_polish_is_on_by_default_and_can_be_turned_off():
    # examples/general_drift.toml has a quadratic cost: P_3's MILP answer (outer approximation)
    # fails Theorem 2.2's conditions at about 1e-4; polished on its face pattern, they hold.
    p = co.load(example("general_drift.toml"))
    on = p.optimize(m=3, certify=True)
    assert on["solution"]["polish"]["applied"]
    assert (
        on["solution"]["polish"]["objective_after"] >= on["solution"]["polish"]["objective_before"]
    )
    assert on["necessary_conditions"]["verdict"] == "holds"
    off = p.optimize(m=3, certify=True, polish=False)
    assert off["solution"].get("polish") is None
    assert off["necessary_conditions"]["verdict"] == "fails"
    assert off["objective"] <= on["objective"]
    with pytest.raises(co.InputError) as e:
        p.optimize(method="local", polish=False)
    assert e.value.field == "polish"


def test_polish_of_a_crawler_p_m_with_an_interior_rate():
    # One link, k = 1, mu+ = 1, mu- = 2, speed 1, T = 10, f2 = (0.6/2) u^2: the optimal rate
    # 5/6 is interior and J* = 1/12 (tests/polish.rs); P_3 polished reaches it exactly.
    c = co.Crawler(blocks=2, stiffness=1.0, mu_forward=1.0, mu_backward=2.0)
    g = co.GaitProblem(period=10.0, max_actuator_speed=1.0, cost=co.Quadratic(0.6))
    r = co.optimize(c, g, method="discrete", m=3)
    assert r.to_dict()["solution"]["polish"]["applied"]
    assert r.objective == pytest.approx(1 / 12, abs=1e-12)
    raw = co.optimize(c, g, method="discrete", m=3, polish=False)
    assert raw.to_dict()["solution"].get("polish") is None
    assert raw.objective < 1 / 12
    with pytest.raises(co.InputError) as e:
        co.optimize(c, g, method="phase", polish=False)
    assert e.value.field == "polish"


def test_general_results_read_back_and_certify(tmp_path):
    # The envelope of every result; the document written, read back checked (the problem
    # rebuilt from it, the solution replayed) and certified: the numbers of optimize(certify=True).
    g = co.load(ONE_LINK)
    r = g.optimize(m=3, certify=True)
    assert r.kind == "general" and r.format == "crawlopt-gait-result" and r.version == 4
    assert r.status == "optimal" and r.certificate["kind"] == "global"
    assert r.problem["problem"]["period"] == 10.0 and "input" not in r.problem
    path = tmp_path / "r.json"
    path.write_text(r.to_json())
    back = co.read_result(path)
    assert isinstance(back, co.GeneralResult)
    assert back.objective == r.objective == pytest.approx(J_STAR, abs=1e-9)
    # Read back, it draws and reports as the object optimize returned.
    assert back.figures()["polytope"].svg == r.figures()["polytope"].svg
    shown = re.search(r'id="objective" data-value="([^"]+)"', back.report()).group(1)
    assert float(shown) == r.objective
    assert np.array_equal(back.u, r.u) and np.array_equal(back.reactions, r.reactions)
    c = back.certify()
    nc = r.necessary_conditions
    assert isinstance(c, co.NecessaryConditions) and c.verdict == "holds"
    assert c["objective"] == nc["objective"]
    assert [k["residual"] for k in c.conditions] == pytest.approx(
        [k["residual"] for k in nc.conditions], abs=1e-12
    )
    # A changed number is refused naming its field.
    for edit, field in [
        (lambda d: d.update(objective=d["objective"] + 0.5), "bad.json: objective"),
        (
            lambda d: d["solution"]["controls"][0].__setitem__(0, 3.0),
            "bad.json: solution.controls[0]",
        ),
        (lambda d: d.update(status="stationary"), "bad.json: status"),
    ]:
        d = json.loads(r.to_json())
        edit(d)
        with pytest.raises(co.InputError) as e:
            co.GeneralResult.from_json(json.dumps(d), "bad.json")
        assert e.value.field == field, str(e.value)
    # The local method's process certifies too; its status is its stop.
    loc = g.optimize(method="local", m=3, shifts=1)
    assert loc.status == "stationary" and loc.certificate["bound"] is None
    assert loc.certify().verdict == "holds"
    # A phase gait certifies on its own phases (the §4 optimum, J = 3): read back or with
    # the optimum, the same certificate.
    ph = g.optimize(method="phase", certify=True)
    assert ph.necessary_conditions.verdict == "holds"
    assert ph.certify().verdict == "holds" and ph.certify().method == "phase"
    same = [json.loads(json.dumps(c.to_dict())) for c in (ph.certify(), ph.necessary_conditions)]
    assert same[0] == same[1]
    # A crawler's result reads as a GaitResult, and is not a general one.
    one = co.load(example("one_link_gait.toml"))
    cr = co.optimize(one.crawler, one.gait_problem, method="phase", phases=2)
    assert cr.kind == "crawler"
    cp = tmp_path / "c.json"
    cp.write_text(cr.to_json())
    back = co.read_result(cp)
    assert isinstance(back, co.GaitResult) and back.to_dict() == cr.to_dict()
    # Either kind's result reads its fields as from a dict, in the one envelope (version 4): a
    # crawler's problem is its file's sections, its solution has its numbers.
    for r in (cr, ph):
        assert set(r.keys()) == set(r.to_dict()) and "solution" in r and r.get("nothing") is None
        assert (r["format"], r["version"], r["objective"]) == (r.format, 4, r.objective)
    assert set(cr["problem"]) == {"crawler", "gait"}
    assert cr["solution"]["displacement_per_period"] == cr.displacement_per_period == cr.objective
    with pytest.raises(co.InputError) as e:
        co.GeneralResult.from_json(cr.to_json())
    assert e.value.field == "result: kind"


def test_a_crawlers_problem_in_general_form_is_recognised_and_takes_the_chains_bound():
    three = co.load(ONE_LINK.replace("general_one_link", "general_three_blocks"))
    structure = [c for c in three.analyze()["checks"] if c["name"] == "structure"][0]
    assert structure["detail"].startswith("a chain: the gait problem of a crawler of 3 blocks")
    r = three.optimize(m=2, bound={"resolution": 4, "box_resolution": 4})
    ub = r["certificate"]["upper_bound"]["value"]
    crawler = co.Crawler(blocks=3, stiffness=1.0, mu_forward=1.0, mu_backward=1.5)
    gait = co.GaitProblem(period=10.0, max_actuator_speed=1.0)
    want = co.optimize(
        crawler, gait, method="discrete", m=2, bound={"resolution": 4, "box_resolution": 4}
    )
    assert ub == pytest.approx(want.certificate["upper_bound"]["value"], rel=1e-12)
    assert r["objective"] == pytest.approx(want.objective, abs=1e-9)
    with pytest.raises(co.InputError) as e:
        co.load(ONE_LINK).optimize(bound=True)
    assert e.value.field == "bound"


def test_the_crawlers_local_methods_on_a_chain():
    # The three-block crawler in general form: the crawler's sequence and chain methods run on
    # the crawler it is, the gait written back (J as the crawler's), a local claim; a problem
    # that is not a crawler's refuses them naming the method.
    g = co.load(example("general_three_blocks.toml"))
    crawler = co.load(example("three_blocks_gait.toml"))
    for method in ("sequence", "chain"):
        r = g.optimize(method=method, certify=True)
        want = co.optimize(crawler.crawler, crawler.gait_problem, method=method)
        assert r.objective == pytest.approx(want.objective, rel=1e-9)
        assert r.method == method and r.status == want.status
        assert r.certificate["kind"] == "local" and r.certificate["bound"] is None
        assert len(r.durations) == r.to_dict()["solution"]["max_phases"]
        assert r.to_pandas().shape[0] == len(r.durations)
        back = co.GeneralResult.from_json(r.to_json())
        assert back.objective == r.objective
        assert r.necessary_conditions.verdict == back.certify().verdict
    with pytest.raises(co.InputError) as e:
        co.load(ONE_LINK).optimize(method="chain")
    assert e.value.field == "method"
    with pytest.raises(co.InputError) as e:
        g.optimize(method="sequence", m=3)
    assert e.value.field == "m"


def test_every_method_takes_the_chains_bound_and_refuses_what_cannot_apply_first(tmp_path):
    # The crawler's local methods on its general form take its upper bound, as every method on
    # (P) does: the crawler's own bound, recorded beside the local certificate, read back.
    g = co.load(example("general_three_blocks.toml"))
    crawler = co.load(example("three_blocks_gait.toml"))
    grid = {"resolution": 2, "box_resolution": 2}
    for method in ("sequence", "chain"):
        r = g.optimize(method=method, bound=grid)
        want = co.optimize(crawler.crawler, crawler.gait_problem, method=method, bound=grid)
        ub = r.certificate["upper_bound"]["value"]
        assert ub == pytest.approx(want.certificate["upper_bound"]["value"], rel=1e-9)
        assert ub >= r.objective and r.certificate["kind"] == "local"
        back = co.GeneralResult.from_json(r.to_json())
        assert back.certificate["upper_bound"]["value"] == ub
    # A bound beyond four blocks, and certify on a Cauchy problem, are refused before the run.
    with pytest.raises(co.InputError) as e:
        co.load(example("general_chain20.toml")).optimize(method="chain", bound=True)
    assert e.value.field == "bound" and "crawler.blocks is 20" in str(e.value)
    text = (
        Path(ONE_LINK)
        .read_text()
        .replace("period = 10.0", "period = 10.0\nperiodic = false\ninitial_state = [0.0]")
    )
    (tmp_path / "cauchy.toml").write_text(text)
    cauchy = co.load(str(tmp_path / "cauchy.toml"))
    for method in ("discrete", "local", "phase"):
        with pytest.raises(co.InputError) as e:
            cauchy.optimize(method=method, certify=True)
        assert e.value.field == "certify"


def test_a_chain_file_is_simulated_with_the_chains_kernels():
    # The 20-block crawler written as (P) under the alternating wave: both methods give the
    # closed form 4 - 1/19, the regime searched by the crawler's simulator on the chain, the
    # catching-up steps projected by the chain's O(N) method (the exact method's tangent cones
    # by the dense one).
    p = co.load(example("general_chain20.toml"))
    for method, projection in (("exact", "dense"), ("catching_up", "chain")):
        s = p.simulate(method=method)
        assert s["regime_search"] == "chain"
        assert s["simulation"]["projection"] == projection
        assert s.objective == pytest.approx(4 - 1 / 19, abs=1e-9)
        assert s["simulation"]["periods"] < 50


def test_a_simulation_of_either_kind_has_one_envelope():
    # The library's document of a simulation (crawlopt::io::SimulationDocument): format,
    # version, kind and objective, the crawler's being its displacement per period (f2 = 0):
    # max(0, 2A - 2) = 4 for one link under a sine of amplitude 3 (theory §10).
    c = co.Crawler(blocks=2, stiffness=1.0, mu_forward=1.0, mu_backward=2.0)
    crawler = co.simulate(c, co.Actuation.sine(period=1.0, amplitude=[3.0]))
    general = co.load(ONE_LINK).simulate()
    for s, kind in ((crawler.to_dict(), "crawler"), (general.to_dict(), "general")):
        assert (s["format"], s["version"], s["kind"]) == ("crawlopt-simulation", 1, kind)
    assert crawler.objective == crawler.displacement_per_period == pytest.approx(4.0, abs=1e-9)
    assert general["objective"] == pytest.approx(J_STAR, abs=1e-9)


def test_the_free_transition_formulation_reaches_the_one_link_optimum_at_two_slots():
    # Slots of a free transition and a phase: the §4 optimum (4 phases) at K = 2, where the
    # general formulation gives 0; the formulation is named in the answer and checked.
    p = co.load(ONE_LINK)
    slots = p.optimize(method="phase", phases=2, formulation="transitions")
    assert slots["objective"] == pytest.approx(J_STAR, abs=1e-7)
    assert slots["formulation"] == "transitions"
    assert len(slots["solution"]["durations"]) == 4
    plain = p.optimize(method="phase", phases=2, formulation="general")
    assert plain["objective"] == pytest.approx(0.0, abs=1e-9)
    # The default on a problem that is not a chain.
    default = p.optimize(method="phase", phases=2)
    assert default["formulation"] == "transitions"
    assert default["objective"] == pytest.approx(J_STAR, abs=1e-7)
    with pytest.raises(co.InputError, match="formulation"):
        p.optimize(method="phase", formulation="bogus")
    with pytest.raises(co.InputError, match="formulation"):
        p.optimize(method="discrete", formulation="general")


def test_a_general_jobs_notes_reach_its_result():
    # The three-block crawler written as (P), by the crawler's sequence method at two slip
    # phases: the best structured gait is returned, and the note saying why is the result's,
    # as a crawler's notes are; a result read back has none.
    r = co.load(example("general_three_blocks.toml")).optimize(method="sequence", phases=2)
    assert len(r.notes) == 1 and "is below the best structured gait" in r.notes[0]
    assert co.GeneralResult.from_json(r.to_json()).notes == []


def test_the_local_method_starts_from_a_given_result():
    # As `crawlopt optimize --method local --start R.json`: a local optimum started from itself
    # is stationary (its J, which is its start's); a crawler's result or another object is
    # refused naming start. The global P_m starts from it as well.
    p = co.load(example("general_three_blocks.toml"))
    first = p.optimize(method="local", m=6, shifts=2)
    again = p.optimize(method="local", m=6, shifts=1, start=first)
    assert again["start_from"] == "start" and again["starts_tried"] == 1
    assert again.solution["start_objective"] == pytest.approx(first.objective, abs=1e-9)
    assert again.objective == pytest.approx(first.objective, abs=1e-9)
    with pytest.raises(co.InputError, match="start"):
        p.optimize(method="local", m=6, start="first.json")
    with pytest.raises(co.InputError, match="start"):
        co.load(ONE_LINK).optimize(method="local", m=6, start=first)
    # The global P_m takes a start too (its process on the grid the MILP's first incumbent),
    # as a crawler's does; the phase method does not.
    pm = p.optimize(method="discrete", m=3, start=first)
    assert pm["discrete_start"]["start"] == "local (start)"
    assert pm["discrete_start"]["start_objective"] <= pm.objective + 1e-9
    with pytest.raises(co.InputError, match="start"):
        p.optimize(method="phase", start=first)
    # A start of a problem with a larger U is no gait of this one: refused naming start and
    # the start's own field.
    narrow = co.load(ONE_LINK)
    wide = co.GeneralProblem(
        normals=[[1.0], [-1.0]],
        offsets=[1.0, 1.0],
        B=[[1.0]],
        lower=[-2.0],
        upper=[2.0],
        zero_mean=True,
        face_weights=[0.5, 0.5],
        period=10.0,
    )
    with pytest.raises(co.InputError, match=r"solution\.controls\[\d+\] = \[-?2\.0\]") as e:
        narrow.optimize(method="local", m=5, start=wide.optimize(method="phase"))
    assert e.value.field == "start"


def test_the_local_method_certifies_as_certify_does():
    # certify=True applies to the local method (it was refused): the conditions attached are
    # those certify() computes on the result read back, as for the global methods.
    p = co.load(example("general_one_link.toml"))
    r = p.optimize(method="local", certify=True)
    assert r.necessary_conditions.verdict == "holds"

    def numbers(d):  # every number as a float (-0.0 == 0.0: a zero's sign is not kept)
        return json.loads(json.dumps(d.to_dict(), default=lambda a: a.tolist()))

    assert numbers(r.necessary_conditions) == numbers(r.certify())


def test_the_local_method_proves_the_chains_upper_bound():
    # bound= applies to the local method where the problem is a crawler's (it was refused):
    # the bound over all periodic gaits, whatever the method, so the global P_m's.
    p = co.load(example("general_three_blocks.toml"))
    bound = {"resolution": 2, "box_resolution": 2}
    r = p.optimize(method="local", bound=bound)
    ub = r.certificate["upper_bound"]["value"]
    assert ub == p.optimize(m=2, bound=bound).certificate["upper_bound"]["value"]
    assert ub >= r.objective and r.certificate["kind"] == "local"
    with pytest.raises(co.InputError) as e:
        co.load(example("general_one_link.toml")).optimize(method="local", bound=bound)
    assert e.value.field == "bound"
