"""Studies through Python give the `pkm` command's numbers to the last bit; their errors
carry key paths; Ctrl-C cancels a running study."""

import json
import subprocess
import signal
import threading
import time
import _thread

import numpy as np
import pytest

import pkm
from conftest import to_toml


def run_command(pkm_command, kind, study, tmp_path):
    path = tmp_path / f"{kind}.toml"
    path.write_text(to_toml(study))
    out = tmp_path / "out"
    subprocess.run([str(pkm_command), kind, str(path), "--out", str(out), "--quiet"], check=True, capture_output=True)
    return path, json.loads((out / "results.json").read_text())


def test_workspace_result_is_the_commands_to_the_last_bit(pkm_command, nuwar_study, tmp_path):
    path, command = run_command(pkm_command, "workspace", nuwar_study, tmp_path)
    from_dict = pkm.workspace(nuwar_study, progress=False)
    from_file = pkm.workspace(str(path), progress=False)
    assert from_dict["result"] == command["result"]
    assert from_file["result"] == command["result"]
    # The same floats, not merely equal after rounding: compare their JSON texts too.
    assert json.dumps(from_dict["result"], sort_keys=True) == json.dumps(command["result"], sort_keys=True)
    assert from_dict["result"]["estimate"]["n_inside"] > 0


def test_workspace_tables_are_arrays_matching_the_commands_csv(pkm_command, nuwar_study, tmp_path):
    _, command = run_command(pkm_command, "workspace", nuwar_study, tmp_path)
    outcome = pkm.workspace(nuwar_study, progress=False)
    table = outcome["tables"]["slice-1-xy.csv"]
    csv = np.genfromtxt(tmp_path / "out" / "slice-1-xy.csv", delimiter=",", names=True)
    for column in ["x", "y", "inverse_condition"]:
        assert isinstance(table[column], np.ndarray) and table[column].dtype == np.float64
        np.testing.assert_array_equal(table[column], csv[column])
    # Membership is a bool column (written 1/0 in the CSV).
    assert table["inside"].dtype == np.bool_
    np.testing.assert_array_equal(table["inside"], csv["inside"] == 1)
    assert "slice-1-xy.svg" in outcome["figures"]
    assert any("W =" in line for line in outcome["summary"])


def test_study_errors_carry_their_key_path(nuwar_study):
    nuwar_study["workspace"]["slices"][0]["cells"] = 0
    with pytest.raises(pkm.InvalidInput) as caught:
        pkm.workspace(nuwar_study, progress=False)
    assert caught.value.key_path == "workspace.slices[0].cells"
    nuwar_study["workspace"]["slices"][0]["cells"] = 12
    nuwar_study["sampling"]["points"] = "many"
    with pytest.raises(pkm.InvalidInput) as caught:
        pkm.workspace(nuwar_study, progress=False)
    assert caught.value.key_path == "sampling.points"


@pytest.mark.parametrize("study", [None, 3.5, "/no/such/study.toml", ["mechanism"]])
def test_unreadable_studies_raise_pkm_errors(study):
    with pytest.raises(pkm.Error):
        pkm.workspace(study, progress=False)


def test_toml_errors_name_their_key(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text('[mechanism.tsai]\na = 0.2\nb = "x"\n')
    with pytest.raises(pkm.InvalidInput) as caught:
        pkm.workspace(path, progress=False)
    assert caught.value.key_path == "mechanism.tsai.b"


def test_progress_reaches_the_callback(nuwar_study):
    seen = []
    pkm._native.workspace(nuwar_study, lambda *a: seen.append(a))
    labels = {label for _, label, _, _ in seen}
    assert "workspace points" in labels or "sampling points" in labels


@pytest.mark.parametrize("interrupt_at", [0.05, 0.5])
def test_keyboard_interrupt_cancels_a_running_study_within_a_second(nuwar_study, interrupt_at):
    # 2^22 points (100 MB): generating them takes a fraction of a second, evaluating them
    # seconds, so the interrupt lands in either phase; both check the cancellation between
    # blocks of 4096 points.
    nuwar_study["sampling"]["points"] = 1 << 20
    nuwar_study["sampling"]["replicates"] = 4
    # Python raises KeyboardInterrupt only under its default SIGINT handler; a process started
    # in the background by a non-interactive shell inherits SIGINT ignored (and then
    # `interrupt_main` does nothing), so the test installs the handler an interactive user has.
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(interrupt_at, _thread.interrupt_main)
    start = time.monotonic()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            pkm.workspace(nuwar_study, progress=False)
    finally:
        timer.cancel()  # never a stray interrupt after the test
        signal.signal(signal.SIGINT, previous)
    elapsed = time.monotonic() - start
    print(f"cancelled {elapsed - interrupt_at:.2f} s after the interrupt")
    assert timer.finished.is_set()
    assert elapsed - interrupt_at < 1.0, f"cancelled {elapsed - interrupt_at:.2f} s after the interrupt"


def test_figures_are_the_commands_svg_files(pkm_command, nuwar_study, tmp_path):
    _, _ = run_command(pkm_command, "workspace", nuwar_study, tmp_path)
    figures = pkm.workspace(nuwar_study, progress=False)["figures"]
    written = sorted(p.name for p in (tmp_path / "out").glob("*.svg"))
    assert sorted(figures) == written and "robot.svg" in written
    for name, figure in figures.items():
        assert isinstance(figure, pkm.Figure) and figure.name == name
        assert figure._repr_svg_() == (tmp_path / "out" / name).read_text()
    figures["slice-1-xy.svg"].save(tmp_path / "saved.svg")
    assert (tmp_path / "saved.svg").read_text().startswith("<svg")
