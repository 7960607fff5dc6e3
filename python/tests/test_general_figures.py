"""The library's figures and report of the general problem (P) from Python: the same figures as
``crawlopt simulate --plot`` and ``optimize --plot``, and the report showing the optimiser's
J."""

import pickle
import re

import crawlopt as co
import pytest


def test_figures_and_report_of_a_general_simulation_and_optimum(tmp_path):
    g = co.load("examples/general_drift.toml")
    sim = g.simulate(steps_per_period=200)
    figs = sim.figures()
    assert list(figs) == ["polytope", "states", "controls", "reactions", "integrand"]
    assert "<svg" in figs["polytope"].svg and "J = " in figs["integrand"].caption
    page = sim.report()
    assert "<h1>Simulation of a general problem (P)</h1>" in page
    r = g.optimize(m=3, certify=True)
    assert "adjoint" in r.figures()
    path = tmp_path / "r.html"
    page = r.report(path, source="general_drift.toml")
    assert path.read_text(encoding="utf-8") == page
    shown = float(re.search(r'id="objective" data-value="([^"]+)"', page).group(1))
    assert shown == r.objective
    assert "crawlopt.GeneralResult.report (Python)" in page
    # A one-state problem: the interval with x(t) over time.
    one = co.load("examples/general_one_link.toml").optimize(method="phase")
    assert "face 1:" in one.figures()["polytope"].svg
    # A copy read back from its document has no record to draw from.
    back = pickle.loads(pickle.dumps(r))
    assert back == r
    with pytest.raises(co.CrawloptError, match="no figures"):
        back.figures()
