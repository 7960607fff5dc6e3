"""examples/tour.ipynb runs top to bottom (nbclient) and shows what it promises."""

import os

import nbformat
from nbclient import NotebookClient


def test_the_tour_runs_and_shows_the_optimum(tmp_path, monkeypatch):
    monkeypatch.setenv("CRAWLOPT_TOUR_OUT", str(tmp_path / "tour_report.html"))
    nb = nbformat.read("examples/tour.ipynb", as_version=4)
    # Run where a user opens it: in examples/.
    NotebookClient(nb, timeout=300, resources={"metadata": {"path": "examples"}}).execute()
    outputs = [o for cell in nb.cells if cell.cell_type == "code" for o in cell.outputs]
    assert not [o for o in outputs if o.output_type == "error"]
    text = "".join(o.get("text", "") + o.get("data", {}).get("text/plain", "") for o in outputs)
    assert "J* = 2.6" in text
    assert "'holds'" in text or "'degenerate'" in text
    svg = [o for o in outputs if "image/svg+xml" in o.get("data", {})]
    assert len(svg) >= 1
    html = [o for o in outputs if "text/html" in o.get("data", {})]
    assert any("<svg" in o["data"]["text/html"] for o in html)  # the result's summary
    assert any("iframe" in o["data"]["text/html"] for o in html)  # the report, inline
    assert os.path.getsize(tmp_path / "tour_report.html") > 10_000
