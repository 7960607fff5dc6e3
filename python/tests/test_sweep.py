"""crawlopt.sweep: the one-link closed form over a grid, and the same rows through a real Dask
cluster of worker processes as in the library's own thread pool."""

import math

import crawlopt as co
import pytest

SPEC = {
    "job": "optimize",
    "model": {
        "crawler": {"blocks": 2, "stiffness": 1.0, "mu_forward": 1.0, "mu_backward": 2.0},
        "gait": {"period": 10.0, "max_actuator_speed": 1.0},
    },
    "axis": [
        {"field": "crawler.mu_forward", "values": [0.5, 1.0, 2.0, 2.5]},
        {"field": "gait.period", "range": {"from": 2.0, "to": 8.0, "count": 4}},
    ],
}


def closed_form(p: float, t: float) -> float:
    """Theory §9 for mu+ = p on both blocks, mu- = 2, k = a = 1."""
    return max(0.0, (t - 4.0 * p) / 2.0) if p < 2.0 else 0.0


def check(df):
    assert list(df.columns[:3]) == ["point", "crawler.mu_forward", "gait.period"]
    assert list(df["point"]) == list(range(16))
    for _, r in df.iterrows():
        p, t = r["crawler.mu_forward"], r["gait.period"]
        if p == 2.0:
            assert r["status"] == "error" and "uniqueness condition" in r["error"]
            assert r["objective"] is None or math.isnan(r["objective"])
        else:
            assert abs(r["objective"] - closed_form(p, t)) <= 1e-9, (p, t)


def test_serial_rows_match_the_closed_form():
    check(co.sweep(SPEC, threads=1))


def test_a_sweep_file_and_bad_specs():
    df = co.sweep("examples/sweep_one_link.toml", threads=2)
    assert len(df) == 64
    bad = dict(SPEC, axis=[{"field": "crawler.mu_fwd", "values": [1.0]}])
    with pytest.raises(co.InputError) as e:
        co.sweep(bad)
    assert e.value.field == "axis[1].field"


def test_one_field_in_two_spellings_and_absurd_threads_are_refused():
    # Issue 30: "gait.period " beside "gait.period" was a second axis whose value won.
    for a, b in [
        ("gait.period", "gait.period "),
        ("crawler.mu_forward[1]", "crawler.mu_forward[ 1 ]"),
        ("crawler.mu_forward", "crawler.mu_forward[2]"),
    ]:
        bad = dict(SPEC, axis=[{"field": a, "values": [6.0, 8.0]}, {"field": b, "values": [20.0]}])
        with pytest.raises(co.InputError) as e:
            co.sweep(bad)
        assert e.value.field == "axis[2].field", str(e.value)
    with pytest.raises(co.InputError) as e:
        co.sweep(SPEC, threads=100000)
    assert e.value.field == "threads"
    with pytest.raises(co.InputError) as e:
        co.sweep(SPEC, threads=-1)
    assert e.value.field == "threads"


def test_dask_local_cluster_gives_the_same_rows():
    import distributed  # pinned in scripts/python-env: a missing one fails, never skips

    serial = co.sweep(SPEC, threads=1)
    with (
        distributed.LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
        ) as cluster,
        distributed.Client(cluster) as client,
    ):
        assert len(client.scheduler_info()["workers"]) == 2
        df = co.sweep(SPEC, executor=client.get_executor())
    cols = [c for c in df.columns if c != "seconds"]
    assert df[cols].fillna(-1).equals(serial[cols].fillna(-1))
    check(df)


GENERAL = {
    "job": "optimize",
    "model": {
        "sweeping_process": {"normals": [[1.0], [-1.0]], "offsets": [1.0, 1.0]},
        "dynamics": {"B": [[1.0]]},
        "control": {"lower": [-1.0], "upper": [1.0]},
        "objective": {"face_weights": [0.5, 0.5]},
        "problem": {"period": 10.0},
    },
    "axis": [
        {"field": "sweeping_process.offsets[2]", "values": [0.5, 1.0, 2.0]},
        {"field": "problem.period", "values": [3.0, 6.0, 10.0]},
    ],
}


def test_a_general_sweep_gives_the_closed_form_in_the_same_table():
    """The paper's §4 one-link problem in general form: J* = max(0, (T - 2 (1 + c_2)) / 2)."""
    df = co.sweep(GENERAL, threads=2)
    crawler = co.sweep(SPEC, threads=1)
    assert list(df.columns[3:]) == list(crawler.columns[3:])
    assert list(df.columns[:3]) == ["point", "sweeping_process.offsets[2]", "problem.period"]
    assert len(df) == 9
    for _, r in df.iterrows():
        c2, t = r["sweeping_process.offsets[2]"], r["problem.period"]
        assert abs(r["objective"] - max(0.0, (t - 2.0 * (1.0 + c2)) / 2.0)) <= 1e-7, (c2, t)
        assert (r["method"], r["certificate"], r["status"]) == ("discrete", "global", "optimal")
    bad = dict(GENERAL, axis=[{"field": "sweeping_process.offsets[3]", "values": [1.0]}])
    with pytest.raises(co.InputError) as e:
        co.sweep(bad)
    assert e.value.field == "axis[1].field"
    assert "entry 3 does not exist" in str(e.value)
