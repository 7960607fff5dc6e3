"""Shared paths: the repository root (examples, the CLI binary built by cargo)."""

import os
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(autouse=True)
def _at_root(monkeypatch):
    """Tests run from the repository root, so that example paths read as in the README."""
    monkeypatch.chdir(ROOT)


@pytest.fixture
def cli():
    """The crawlopt binary built by `cargo build --release`."""
    path = ROOT / "target" / "release" / "crawlopt"
    if not path.exists():
        pytest.fail("target/release/crawlopt is missing: run `cargo build --release` first")
    return str(path)


def example(name: str) -> str:
    return os.path.join("examples", name)
