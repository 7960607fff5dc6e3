"""co.fit: simulate-then-fit round trips, the typed result, bad inputs."""

import crawlopt as co
import numpy as np
import pytest


def _record(crawler, act, periods=2, frames=64):
    """The simulated orbit filmed at ``frames`` per period: positions are linear between the
    simulator's samples (exact method, piecewise-linear actuation), so interpolation is exact."""
    s = co.simulate(crawler, act, periods=periods)
    t = np.arange(frames * periods + 1) * act.period / frames
    X = np.column_stack([np.interp(t, s.t, s.X[:, b]) for b in range(s.X.shape[1])])
    return t, act(t), X


def _gait():
    times = np.arange(8) / 8.0
    tri = [[1 - abs(2 * ((tt - lag) % 1.0) - 1) for lag in (0.0, 1 / 3)] for tt in times]
    L = 3.0 * np.array(tri)
    return co.Actuation.piecewise_linear(1.0, times, L)


def test_exact_data_recover_the_identified_parameters():
    c = co.Crawler(3, [2.0, 0.5], [1.0, 1.5, 0.8], [2.0, 2.5, 1.7])
    t, L, X = _record(c, _gait())
    r = co.fit(t, L, X, blocks=3, fix={"stiffness[1]": 2.0})
    assert isinstance(r, co.FitResult)
    truth = {"stiffness": [2.0, 0.5], "mu_forward": [1.0, 1.5, 0.8], "mu_backward": [2.0, 2.5, 1.7]}
    known = 0
    for name, values in truth.items():
        for est, iv, v in zip(r.crawler[name], r.intervals[name], values):
            lo, hi = iv
            assert lo <= v * (1 + 1e-9) and (hi is None or v <= hi * (1 + 1e-9))
            if est is not None:
                assert abs(est - v) <= 1e-9 * v
                known += 1
    assert known >= 6
    assert r.scale["fixed"] == [{"parameter": "stiffness[1]", "value": 2.0}]
    assert isinstance(r.fitted, co.Crawler) and r.fitted.blocks == 3
    assert r.predicted.shape == X.shape
    assert r.prediction["max"] >= 0 and r.to_dict()["samples"] == len(t)


def test_without_a_fix_the_result_names_the_reference():
    c = co.Crawler(2, 1.5, [1.0, 1.2], [1.4, 0.9])
    act = co.Actuation.piecewise_linear(1.0, [0.0, 0.5], [[0.0], [4.0]])
    t, L, X = _record(c, act)
    r = co.fit(t, L[:, 0], X, blocks=2)
    assert r.scale["ratios_to"] == "stiffness[1]"
    assert r.crawler["stiffness"] == [1.0]
    assert abs(r.crawler["mu_forward"][1] - 1.2 / 1.5) < 1e-9


def test_bad_inputs_name_the_field():
    t = np.arange(6.0)
    L = np.zeros((6, 1))
    X = np.zeros((6, 2))
    with pytest.raises(co.InputError) as e:
        co.fit(t[::-1], L, X, blocks=2)
    assert "row 2, column t" in str(e.value)
    X2 = X.copy()
    X2[3, 1] = np.nan
    with pytest.raises(co.InputError) as e:
        co.fit(t, L, X2, blocks=2)
    assert "row 4, column X_2" in str(e.value)
    with pytest.raises(co.InputError) as e:
        co.fit(t, L, X, blocks=3)
    assert e.value.field.startswith("L") or e.value.field.startswith("X")
    with pytest.raises(co.InputError) as e:
        co.fit(t[:3], L[:3], X[:3], blocks=2)
    assert e.value.field == "samples"
    with pytest.raises(co.InputError) as e:
        co.fit(t, L, X, blocks=2, fix={"k[1]": 1.0})
    assert e.value.field == "fix"
    with pytest.raises(co.InputError):
        co.fit(t, L, X[:, 0], blocks=2)
    with pytest.raises(co.InputError):
        co.fit(t, L, X, blocks=1)


def test_noisy_data_lie_inside_the_intervals_and_the_fitted_model_runs():
    c = co.Crawler(3, [2.0, 0.5], [1.0, 1.5, 0.8], [2.0, 2.5, 1.7])
    act = _gait()
    t, L, X = _record(c, act, periods=3, frames=40)
    rng = np.random.default_rng(29)
    r = co.fit(t, L, X + 1e-3 * rng.standard_normal(X.shape), blocks=3, fix={"stiffness[1]": 2.0})
    assert r.noise["estimated"] and r.noise["sigma"] > 0
    truth = {"stiffness": [2.0, 0.5], "mu_forward": [1.0, 1.5, 0.8], "mu_backward": [2.0, 2.5, 1.7]}
    for name, values in truth.items():
        for (lo, hi), v in zip(r.intervals[name], values):
            assert lo <= v and (hi is None or v <= hi), (name, lo, hi, v)
    s = co.simulate(r.fitted, act)
    assert s.converged
