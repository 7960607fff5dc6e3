"""The package's PEP 517 build backend: maturin, with the two build tools of the HiGHS solver
(cmake, and libclang for its generated bindings) taken from the build requirements.

`pip install ./python` and `pip wheel ./python` install `cmake` and `libclang` from the package
registry into the isolated build environment (see ``[build-system] requires`` in
pyproject.toml); this module points the Rust build at them (the ``CMAKE`` and ``LIBCLANG_PATH``
variables read by the ``cmake`` and ``bindgen`` crates) and hands every hook to maturin
unchanged. A caller that sets either variable keeps it.
"""

from __future__ import annotations

import os

import maturin


def _build_tools() -> None:
    """Sets CMAKE and LIBCLANG_PATH from the cmake and libclang packages, unless already set."""
    if "CMAKE" not in os.environ:
        import cmake

        os.environ["CMAKE"] = os.path.join(cmake.CMAKE_BIN_DIR, "cmake")
    if "LIBCLANG_PATH" not in os.environ:
        import clang

        os.environ["LIBCLANG_PATH"] = os.path.join(os.path.dirname(clang.__file__), "native")


def build_wheel(wheel_directory, config_settings=None, metadata_directory=None):
    _build_tools()
    return maturin.build_wheel(wheel_directory, config_settings, metadata_directory)


def build_editable(wheel_directory, config_settings=None, metadata_directory=None):
    _build_tools()
    return maturin.build_editable(wheel_directory, config_settings, metadata_directory)


# The other hooks are maturin's own.
build_sdist = maturin.build_sdist
get_requires_for_build_wheel = maturin.get_requires_for_build_wheel
get_requires_for_build_editable = maturin.get_requires_for_build_editable
get_requires_for_build_sdist = maturin.get_requires_for_build_sdist
prepare_metadata_for_build_wheel = maturin.prepare_metadata_for_build_wheel
