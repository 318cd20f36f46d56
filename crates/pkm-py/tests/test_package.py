"""The package: version, the exception hierarchy, presets, the type stubs."""

import ast
import pathlib

import pkm


def test_version_is_the_crate_version():
    cargo = (pathlib.Path(__file__).resolve().parents[3] / "Cargo.toml").read_text()
    line = next(l for l in cargo.splitlines() if l.startswith("version = "))
    assert pkm.__version__ == line.split('"')[1]


def test_exceptions_form_one_hierarchy():
    for name in ["InvalidInput", "Infeasible", "NotConverged", "Cancelled"]:
        assert issubclass(getattr(pkm, name), pkm.Error)
    assert issubclass(pkm.Error, Exception)
    assert not issubclass(pkm.Error, KeyboardInterrupt)


def test_every_preset_builds_and_round_trips_through_its_dict():
    presets = pkm.presets()
    assert set(presets) >= {"nuwar", "delta", "tsai", "three_upu", "stewart_gough"}
    for name, entry in presets.items():
        by_name = pkm.Mechanism(name)
        by_dict = pkm.Mechanism(entry["mechanism"])
        assert by_name.design() == by_dict.design(), name
        assert by_name.kind in entry["mechanism"]


def _stub_names(path):
    tree = ast.parse(path.read_text())
    names = set()
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            names.add(node.name)
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            names.add(node.target.id)
    return names


def test_stubs_declare_every_public_name():
    # The extension module's stub (`mypy.stubtest pkm._native` in .ci/run checks signatures
    # too); the package's own names are annotated in __init__.py.
    stub = pathlib.Path(pkm.__file__).with_name("_native.pyi")
    declared = _stub_names(stub)
    missing = [n for n in pkm._native.__all__ if n not in declared]
    assert not missing, f"not in _native.pyi: {missing}"
    assert not pathlib.Path(pkm.__file__).with_name("__init__.pyi").exists()
    assert all(hasattr(pkm, n) for n in pkm.__all__)
    methods = {
        n.name
        for c in ast.parse(stub.read_text()).body
        if isinstance(c, ast.ClassDef) and c.name == "Mechanism"
        for n in c.body
        if isinstance(n, ast.FunctionDef)
    }
    public = {n for n in dir(pkm.Mechanism) if not n.startswith("_")}
    assert public <= methods, f"Mechanism members not in the stub: {public - methods}"


def test_docstrings_read_in_help():
    assert "preset" in pkm.Mechanism.__doc__
    assert "N × 3" in pkm.Mechanism.inverse_kinematics.__doc__
    assert "results.json" in pkm.workspace.__doc__


def test_the_quickstart_runs_end_to_end(tmp_path):
    import subprocess
    import sys

    script = pathlib.Path(__file__).resolve().parents[3] / "examples" / "python" / "quickstart.py"
    run = subprocess.run([sys.executable, str(script)], cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    for expected in ["W = ", "IK → FK round trip", "on the front", "samples every"]:
        assert expected in run.stdout, run.stdout
