"""Every exception type with its fields; no panic crosses into Python."""

import crawlopt as co
import pytest


def test_input_error_names_the_field_and_value():
    m = co.load("examples/three_blocks_gait.toml")
    with pytest.raises(co.InputError) as e:
        co.optimize(m.crawler, m.gait_problem, m=3)
    assert e.value.field == "m" and e.value.value == "3"
    assert 'applies to method="discrete" only' in str(e.value)
    assert isinstance(e.value, ValueError)
    with pytest.raises(co.InputError) as e:
        co.optimize(m.crawler, m.gait_problem, method="fast")
    assert e.value.field == "method"
    with pytest.raises(co.InputError) as e:
        co.Crawler(blocks=3, mu_forward=[1.0, -1.0, 1.0])
    assert e.value.field == "crawler.mu_forward[2]" and e.value.value == "-1"
    with pytest.raises(co.InputError) as e:
        co.optimize(m.crawler, m.gait_problem, time_limit=-1.0)
    assert e.value.field == "time_limit"


def test_whole_numbers_out_of_range_name_the_setting():
    # A negative or too large count is an InputError naming it, not the extension's bare
    # OverflowError; within range, the library's own check names it too (phases=0).
    m = co.load("examples/three_blocks_gait.toml")
    c, gp = m.crawler, m.gait_problem
    general = co.load("examples/general_one_link.toml")
    cases = [
        (lambda: co.optimize(c, gp, phases=-1), "phases"),
        (lambda: co.optimize(c, gp, max_phases=-2), "max_phases"),
        (lambda: co.optimize(c, gp, method="discrete", m=2**32), "m"),
        (lambda: co.optimize(c, gp, phases=2, bound={"resolution": -1}), "bound.resolution"),
        (
            lambda: co.optimize(c, gp, phases=2, bound={"cost_tangents": 2**70}),
            "bound.cost_tangents",
        ),
        (
            lambda: co.simulate(
                c,
                m.actuation or co.Actuation.sine(period=1.0, amplitude=[1.0, 1.0]),
                steps_per_period=-5,
            ),
            "steps_per_period",
        ),
        (lambda: general.optimize(phases=-1, method="phase"), "phases"),
        (lambda: general.simulate(max_periods=-1), "max_periods"),
        (lambda: co.optimize(c, gp, phases=0), "phases"),
    ]
    for call, field in cases:
        with pytest.raises(co.InputError) as e:
            call()
        assert e.value.field == field, str(e.value)


def test_non_unique_error_carries_the_subset():
    c = co.Crawler(blocks=2, mu_forward=1.0, mu_backward=1.0)
    act = co.Actuation.sine(period=1.0, amplitude=[1.0])
    with pytest.raises(co.NonUniqueError) as e:
        co.simulate(c, act)
    assert e.value.subset in ([1], [2])
    assert e.value.forward_sum == pytest.approx(e.value.backward_sum)
    assert isinstance(e.value, co.InputError)
    assert c.analyze().uniqueness_ok is False


def test_file_error_names_the_path(tmp_path):
    with pytest.raises(co.FileError) as e:
        co.load(tmp_path / "missing.toml")
    assert e.value.field.endswith("missing.toml")
    with pytest.raises(co.InputError):
        co.GaitResult.from_json('{"format": "crawlopt-gait-result"}')


def test_time_limit_without_a_gait_raises():
    # A limit of a nanosecond has passed before the first solve of the start gait ends (10 ms
    # did not: on a fast machine the start was found within it and returned, status
    # "time_limit"). The discrete method has no structured floor (its answer is P_m's).
    c = co.Crawler(blocks=6, mu_backward=1.63)
    with pytest.raises(co.TimeLimitError) as e:
        co.optimize(c, co.GaitProblem(period=10), method="discrete", m=4, time_limit=1e-9)
    assert e.value.incumbent is None
    assert isinstance(e.value, co.CrawloptError)


def test_time_limit_spent_returns_the_structured_floor():
    # The other methods evaluate the structured gaits first and never return less: a limit
    # spent before the method has a gait returns the best of them, status "time_limit".
    c = co.Crawler(blocks=6, mu_backward=1.63)
    r = co.optimize(c, co.GaitProblem(period=10), method="local", m=4, time_limit=1e-9)
    assert r.status == "time_limit"
    assert r.structured["origin"].startswith("structured: ")
    assert r.certificate["gap"] is None


def test_infeasible_and_numerical_errors_are_crawlopt_errors():
    assert issubclass(co.InfeasibleError, co.CrawloptError)
    assert issubclass(co.NumericalError, co.CrawloptError)
    assert issubclass(co.InadmissibleError, co.InputError)


def test_inadmissible_initial_state():
    m = co.load("examples/three_blocks_sine.toml")
    with pytest.raises(co.InadmissibleError) as e:
        co.simulate(m.crawler, m.actuation, initial_state=[100.0, 0.0])
    assert "initial_state" in e.value.field


def test_wrong_types_raise_type_error():
    """Issue 30, item 14: a string for the crawler was an AttributeError from inside."""
    c = co.Crawler(blocks=3)
    a = co.Actuation.sine(1.0, [1.0, 1.0])
    for call, name in [
        (lambda: co.simulate("x", a), "crawler"),
        (lambda: co.simulate(c, "x"), "actuation"),
        (lambda: co.optimize("x", co.GaitProblem(period=10.0)), "crawler"),
        (lambda: co.optimize(c, "x"), "problem"),
        (lambda: co.optimize(c, co.GaitProblem(period=10.0), start="x"), "start"),
    ]:
        with pytest.raises(TypeError) as e:
            call()
        assert str(e.value).startswith(f"{name}: must be a crawlopt.")


def test_arrays_of_the_wrong_shape_are_refused_not_flattened():
    """Issue 30, item 14: an amplitude of shape (2, 1) was silently flattened to two links."""
    import numpy as np

    c = co.Crawler(blocks=3)
    a = co.Actuation.sine(1.0, [1.0, 1.0])
    col = np.ones((2, 1))
    for call, field in [
        (lambda: co.Actuation.sine(1.0, col), "actuation.amplitude"),
        (lambda: co.Actuation.triangle(1.0, [1.0, 1.0], phase_deg=col), "actuation.phase_deg"),
        (lambda: co.Actuation.sine(1.0, [1.0, 1.0], mean=col), "actuation.mean"),
        (lambda: co.Actuation.piecewise_linear(1.0, col, [[0, 0], [1, 1]]), "actuation.times"),
        (
            lambda: co.Actuation.piecewise_linear(1.0, [0, 0.5], np.ones((2, 2, 1))),
            "actuation.lengths",
        ),
        (
            lambda: co.Actuation.piecewise_linear(1.0, [0, 0.5], [[0.0], [[1.0]]]),
            "actuation.lengths[2]",
        ),
        (lambda: co.Crawler(blocks=3, mu_forward=np.ones((3, 1))), "crawler.mu_forward"),
        (lambda: co.Crawler(blocks=3, stiffness=col), "crawler.stiffness"),
        (lambda: co.simulate(c, a, initial_state=np.zeros((2, 1))), "initial_state"),
        (
            lambda: co.optimize(c, co.GaitProblem(period=10.0, max_actuator_speed=col)),
            "gait.max_actuator_speed",
        ),
        (lambda: c.vm(col), "rates"),
        (lambda: a(col), "t"),
    ]:
        with pytest.raises(co.InputError) as e:
            call()
        assert isinstance(e.value, ValueError)
        assert e.value.field == field, str(e.value)
        assert "shape" in str(e.value), str(e.value)
    # The shapes that are meant still work: a number, one per link.
    assert co.Actuation.sine(1.0, 2.0)(0.25).shape == (1, 1)
    assert co.Actuation.sine(1.0, np.array([1.0, 2.0]))([0.0, 0.25]).shape == (2, 2)


def test_a_tolerance_beyond_its_range_is_refused():
    """Issue 30, item 5: tol = 0.5 took a transient's first period for the orbit."""
    m = co.load("examples/three_blocks_sine.toml")
    for tol in [0.5, 1e300]:
        with pytest.raises(co.InputError) as e:
            co.simulate(m.crawler, m.actuation, tol=tol)
        assert e.value.field == "tol" and "(0, 1e-3]" in str(e.value)


def test_settings_reach_the_library_by_their_names():
    # The keywords are read by the library's one settings struct: a refused value names its
    # keyword (a wrong type is a TypeError), on a crawler and on a general problem alike.
    m = co.load("examples/three_blocks_gait.toml")
    general = co.load("examples/general_one_link.toml")
    with pytest.raises(TypeError) as e:
        co.optimize(m.crawler, m.gait_problem, method="discrete", m="three")
    assert str(e.value).startswith("m: invalid type")
    with pytest.raises(TypeError) as e:
        general.optimize(method="phase", certify="yes")
    assert str(e.value).startswith("certify: invalid type")
    # The bound's dict is a table of keys inside them, each named by its path.
    with pytest.raises(TypeError) as e:
        co.optimize(m.crawler, m.gait_problem, bound=3)
    assert str(e.value).startswith("bound: invalid type")
    with pytest.raises(TypeError) as e:
        co.optimize(m.crawler, m.gait_problem, bound={"resolution": "fine"})
    assert str(e.value).startswith("bound.resolution: invalid type")
    # The library's typed error (not its wording) makes it a TypeError, its key and value kept.
    assert (e.value.field, e.value.value) == ("bound.resolution", '"fine"')
    for call, field in [
        (lambda: co.optimize(m.crawler, m.gait_problem, time_limit=float("nan")), "time_limit"),
        (lambda: general.optimize(method="phase", formulation="best"), "formulation"),
        (lambda: general.optimize(method="fastest"), "method"),
    ]:
        with pytest.raises(co.InputError) as e:
            call()
        assert e.value.field == field, str(e.value)
