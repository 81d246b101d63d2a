"""The packages export only their API (docs/python.md): each package's
`__all__` names public objects that exist, `from package import *` gives
exactly those names, and a package namespace re-exports no private helper of
its modules (a name with a leading underscore there is at most a submodule,
such as the compiled slipstrip._slipstrip).

Run: PYTHONPATH=$PWD/python /usr/bin/python3 -m pytest -q tests/python/test_package_exports.py
"""
import importlib
import types

import pytest

PACKAGES = ["slipstrip", "slipstrip.analysis", "slipstrip.report", "slipstrip.scan"]
MODULES_WITH_ALL = ["slipstrip.config", "slipstrip.paths", "slipstrip.plots", "slipstrip.runfile"]
# Each test takes the slipstrip_module fixture: it skips (with the build
# command) when the compiled bindings are not built.


@pytest.mark.parametrize("name", PACKAGES + MODULES_WITH_ALL)
def test_all_names_only_public_objects_that_exist(name, slipstrip_module):
    module = importlib.import_module(name)
    exported = list(module.__all__)
    assert len(exported) == len(set(exported)), f"{name}.__all__ lists a name twice"
    assert [n for n in exported if n.startswith("_")] == [], f"{name}.__all__ exports private names"
    assert [n for n in exported if not hasattr(module, n)] == [], f"{name}.__all__ names what is not there"


@pytest.mark.parametrize("name", PACKAGES + MODULES_WITH_ALL)
def test_star_import_gives_exactly_the_api(name, slipstrip_module):
    namespace = {}
    exec(f"from {name} import *", namespace)
    namespace.pop("__builtins__", None)
    assert set(namespace) == set(importlib.import_module(name).__all__)
    assert [n for n in namespace if n.startswith("_")] == []


@pytest.mark.parametrize("name", PACKAGES)
def test_a_package_reexports_no_private_helper(name, slipstrip_module):
    module = importlib.import_module(name)
    private = []
    for key, value in vars(module).items():
        if not key.startswith("_") or (key.startswith("__") and key.endswith("__")):
            continue
        if isinstance(value, types.ModuleType) and value.__name__.startswith(name + "."):
            continue  # a submodule (slipstrip._slipstrip, the compiled bindings)
        private.append(key)
    assert private == [], f"{name} re-exports private names {private}"
