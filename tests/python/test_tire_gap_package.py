"""The Python package tire_gap (crates/tire-gap-py), installed into .venv by the set-up:
the same numbers as the command line from a DataFrame and from files, errors as
TireGapError naming where, the report's parts, Ctrl-C, and many programmes on Dask."""

import json
import os
import pickle
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import tire_gap
from tire_gap import TireGapError

REPO = Path(__file__).resolve().parents[2]
# Small programmes keep each diagnosis to seconds; one fold assignment for the verdict.
OPTIONS = {"stability_draws": 1}
CLI_OPTIONS = ["--stability-draws", "1"]


@pytest.fixture(scope="session")
def cli():
    """The command line, built as the README builds it."""
    subprocess.run(
        ["cargo", "build", "--release", "--quiet", "-p", "tire-gap", "--bin", "tire-gap"],
        cwd=REPO, check=True,
    )
    return str(REPO / "target" / "release" / "tire-gap")


@pytest.fixture(scope="session")
def programme(cli, tmp_path_factory):
    """A synthetic programme with the temperature effect: the CLI's CSV and the package's
    DataFrame of the same seed, and the CLI's JSON report of the CSV."""
    d = tmp_path_factory.mktemp("programme")
    csv = d / "rig.csv"
    args = ["--seed", "3", "--effects", "temperature", "--rows", "2000"]
    subprocess.run([cli, "synth", *args, "--out", str(csv)], check=True)
    frame = tire_gap.synth(seed=3, effects=["temperature"], rows=2000)
    report = subprocess.run(
        [cli, "diagnose", str(csv), "--json", *CLI_OPTIONS], check=True, capture_output=True,
        text=True,
    ).stdout
    return csv, frame, report


def without_source_names(report: dict) -> dict:
    """The report less what names the input (file name, SHA-256, format)."""
    r = dict(report)
    r.pop("provenance")
    r["blocks"] = json.loads(json.dumps(r["blocks"]))
    for block in r["blocks"]["blocks"]:
        block.pop("file")
    return r


def test_synth_gives_the_numbers_of_the_command_lines_csv(programme, tmp_path):
    csv, frame, _ = programme
    from_file = pd.read_csv(csv)
    assert list(frame.columns) == list(from_file.columns)
    pd.testing.assert_frame_equal(frame, from_file, check_exact=True)
    assert frame.attrs["truth"]["effects"][0]["effect"] == "temperature"
    # Written by the package: the command line's file, byte for byte.
    tire_gap.synth(seed=3, effects=["temperature"], rows=2000, out=tmp_path / "py.csv")
    assert (tmp_path / "py.csv").read_bytes() == csv.read_bytes()
    tydex = tmp_path / "tdx"
    tire_gap.synth(seed=3, rows=1000, out=tydex, format="tydex", tydex_units="si")
    assert len(list(tydex.glob("*.tdx"))) == tire_gap.synth(seed=3, rows=1000)["run"].nunique()
    with pytest.raises(TireGapError, match='format = "xml": unknown; known: csv, tydex'):
        tire_gap.synth(out=tmp_path / "x", format="xml")


def test_a_file_gives_the_command_lines_json_byte_for_byte(programme):
    csv, _, cli_json = programme
    report = tire_gap.diagnose(str(csv), **OPTIONS)
    assert report.to_json() + "\n" == cli_json
    assert report.verdict == ["temperature"]


def test_a_dataframe_gives_the_same_numbers_as_the_file(programme):
    csv, frame, cli_json = programme
    report = tire_gap.diagnose(frame, **OPTIONS)
    ours, theirs = json.loads(report.to_json()), json.loads(cli_json)
    assert without_source_names(ours) == without_source_names(theirs)
    assert ours["provenance"]["input"] == "DataFrame"
    assert ours["provenance"]["inputs"][0]["format"] == "dataframe"
    # The same frame read back from the CSV by pandas: the same report again.
    again = tire_gap.diagnose(pd.read_csv(csv), **OPTIONS)
    assert again.to_json() == report.to_json()


def test_the_reports_parts_are_attributes_and_dataframes(programme):
    csv, _, cli_json = programme
    report = tire_gap.diagnose(csv, **OPTIONS)
    data = json.loads(cli_json)
    assert report.rows == data["rows"] and report.runs == data["runs"]
    base = report.baseline_df
    assert list(base["channel"]) == [b["channel"] for b in data["baseline"]]
    assert np.allclose(base["heldout.rms"], [b["heldout"]["rms"] for b in data["baseline"]], rtol=0)
    assert (base["gap"] > 0).all()
    cand = report.candidates_df
    first = cand[cand["round"] == 1]
    assert set(first["effect"]) == {t["effect"] for t in data["rounds"][0]["trials"]}
    winner = first[first["selected"]]
    assert set(winner["effect"]) == {"temperature"}
    # Held-out error falls where the winner acts.
    assert (winner["heldout_after"] < winner["heldout_before"]).any()
    assert len(report.regions_df) == len(data["regions"])
    assert list(report.remaining_df["channel"]) == list(base["channel"])
    # The ceiling: per channel the 1987 model, the verdict's model and the floor as the JSON
    # has them, an MF 6.1 reference for Fx and Fy.
    ceiling = report.ceiling_df
    assert list(ceiling["channel"]) == list(base["channel"])
    assert np.allclose(ceiling["baseline_rms"], base["heldout.rms"], rtol=0)
    assert np.allclose(ceiling["floor.rms"], [c["floor"]["rms"] for c in data["ceiling"]], rtol=0)
    assert (ceiling["floor.rms"] > 0).all()
    with_reference = ceiling[ceiling["channel"] != "Mz"]
    assert (with_reference["reference.heldout_rms"] > 0).all()
    assert all(w.startswith(c + ": held-out RMS") for c, w in zip(ceiling["channel"], ceiling["words"]))
    assert report.table("extrapolation").shape[0] == len(data["extrapolation"])
    with pytest.raises(KeyError, match="baseline"):
        report.table("nonsense")
    assert "temperature" in report.text()
    assert "temperature" in repr(report)


def test_params_and_plots_are_those_of_the_command_line(programme, cli, tmp_path):
    csv, _, _ = programme
    cli_params = tmp_path / "cli.json"
    subprocess.run(
        [cli, "diagnose", str(csv), *CLI_OPTIONS, "--params", str(cli_params)],
        check=True, capture_output=True,
    )
    report = tire_gap.diagnose(csv, **OPTIONS)
    params = report.params(tmp_path / "ours.json")
    assert params == json.loads(cli_params.read_text())
    assert (tmp_path / "ours.json").read_text() == cli_params.read_text()
    index = report.plots(tmp_path / "figures")
    assert index.is_file()
    assert len(list((tmp_path / "figures").glob("*.svg"))) >= 3


def test_a_report_survives_pickling_without_its_native_part(programme):
    csv, _, _ = programme
    report = tire_gap.diagnose(csv, **OPTIONS)
    back = pickle.loads(pickle.dumps(report))
    assert back.to_json() == report.to_json()
    assert back.text() == report.text()
    assert back.params() == report.params()
    with pytest.raises(TireGapError, match="where the diagnosis ran"):
        back.plots("unused")


def test_options_are_checked_as_on_the_command_line(programme):
    _, frame, _ = programme
    with pytest.raises(TireGapError, match=r"folds = 2 is out of range: it must lie in 3..=20"):
        tire_gap.diagnose(frame, folds=2)
    with pytest.raises(TireGapError, match="unknown effect `warp`"):
        tire_gap.diagnose(frame, effects="temperature,warp")
    report = tire_gap.diagnose(frame, effects=["inflation_pressure"], **OPTIONS)
    assert report.verdict != ["temperature"]
    skipped = {u["effect"] for u in report.untestable}
    assert "temperature" in skipped
    with pytest.raises(TireGapError, match="--rows 5 is out of range"):
        tire_gap.synth(rows=5)


def small_frame():
    return tire_gap.synth(seed=4, rows=1000)


def test_a_missing_column_is_named():
    with pytest.raises(TireGapError) as e:
        tire_gap.diagnose(small_frame().drop(columns=["fz_N"]))
    assert e.value.kind == "input"
    assert e.value.column == "fz_N"
    assert "missing required column" in e.value.message


def test_nan_loads_are_named_by_column_and_rows():
    frame = small_frame()
    frame.loc[[5, 9, 700], "fz_N"] = np.nan
    with pytest.raises(TireGapError) as e:
        tire_gap.diagnose(frame)
    assert (e.value.column, e.value.rows, e.value.file) == ("fz_N", [5, 9, 700], "DataFrame")
    assert str(e.value).startswith("DataFrame: column fz_N: 3 rows (5, 9, 700): missing or not finite")


def test_wrong_units_and_text_in_numbers_are_named():
    frame = small_frame().rename(columns={"alpha_deg": "alpha_grad"})
    with pytest.raises(TireGapError, match='unit "grad" is not accepted for alpha') as e:
        tire_gap.diagnose(frame)
    assert e.value.column == "alpha_grad"
    # Loads in kN under a column that says N would be below the load range; loads in N under
    # a column that says kN are above it.
    frame = small_frame().rename(columns={"fz_N": "fz_kN"})
    with pytest.raises(TireGapError, match="outside the plausible range") as e:
        tire_gap.diagnose(frame)
    assert e.value.column == "fz_kN" and len(e.value.rows) > 100
    frame = small_frame()
    frame["kappa"] = frame["kappa"].astype(object)
    frame.loc[3, "kappa"] = "n/a"
    with pytest.raises(TireGapError, match="not numbers") as e:
        tire_gap.diagnose(frame)
    assert (e.value.column, e.value.rows) == ("kappa", [3])


def test_bad_files_are_named_by_file_and_line(tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text("run,fz_N,alpha_deg,fy_N\n1,4000,1.0,500\n1,abc,2.0,900\n")
    with pytest.raises(TireGapError) as e:
        tire_gap.diagnose(bad)
    assert (e.value.file, e.value.line, e.value.column) == (str(bad), 3, "fz_N")
    assert str(e.value) == f'{bad}:3: column fz_N: "abc" is not a number'
    with pytest.raises(TireGapError, match="cannot read"):
        tire_gap.diagnose(tmp_path / "missing.csv")
    with pytest.raises(TypeError, match="DataFrame, a path, or a list of paths"):
        tire_gap.diagnose(42)


def test_help_and_stubs_describe_the_api():
    doc = tire_gap.diagnose.__doc__
    for word in ("DataFrame", "TYDEX", "folds", "TireGapError", "KeyboardInterrupt"):
        assert word in doc
    package = Path(tire_gap.__file__).parent
    assert (package / "py.typed").is_file()
    assert "def diagnose_columns" in (package / "_native.pyi").read_text()
    assert tire_gap.EFFECTS[0] == "combined_slip" and "temperature" in tire_gap.EFFECTS


def test_ctrl_c_stops_a_long_diagnosis(tmp_path):
    # Ctrl-C raises KeyboardInterrupt in the child even when this process was started with
    # SIGINT ignored (as a background job of a shell is), which the child would inherit.
    script = (
        "import signal, sys, tire_gap\n"
        "signal.signal(signal.SIGINT, signal.default_int_handler)\n"
        "frame = tire_gap.synth(seed=1, rows=200000)\n"
        "print('started', flush=True)\n"
        "try:\n"
        "    tire_gap.diagnose(frame)\n"
        "except KeyboardInterrupt:\n"
        "    print('interrupted', flush=True)\n"
        "    sys.exit(7)\n"
    )
    p = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True)
    assert p.stdout.readline().strip() == "started"
    time.sleep(0.5)
    sent = time.monotonic()
    p.send_signal(signal.SIGINT)
    out, _ = p.communicate(timeout=120)
    assert p.returncode == 7, out
    assert "interrupted" in out
    # The work stops at its next step, not at the end of the diagnosis (seconds here).
    assert time.monotonic() - sent < 60


# Many programmes on Dask ---------------------------------------------------------------------


@pytest.fixture(scope="module")
def batch(cli, tmp_path_factory):
    d = tmp_path_factory.mktemp("batch")
    programmes = []
    for seed, effect in [(11, "temperature"), (12, "inflation_pressure"), (13, "temperature")]:
        path = d / f"tire{seed}.csv"
        subprocess.run(
            [cli, "synth", "--seed", str(seed), "--effects", effect, "--rows", "1500",
             "--out", str(path)],
            check=True,
        )
        programmes.append(str(path))
    corrupt = d / "corrupt.csv"
    corrupt.write_text("run,fz_N,alpha_deg,fy_N\n1,4000,1.0,500\n1,4000,\n")
    programmes.insert(1, str(corrupt))
    return d, programmes


def test_diagnose_many_matches_one_by_one_and_survives_a_corrupt_file(batch, tmp_path):
    from distributed import Client, LocalCluster

    _, programmes = batch
    with LocalCluster(n_workers=2, threads_per_worker=1, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        outcomes = tire_gap.diagnose_many(
            programmes, client=client, progress=False, plots_dir=tmp_path, **OPTIONS)
        workers = {o.worker for o in outcomes}
    figures = sorted(p.parent.name for p in tmp_path.glob("*/index.html"))
    assert figures == ["tire11.csv", "tire12.csv", "tire13.csv"]
    assert [o.name for o in outcomes] == programmes
    assert [o.ok for o in outcomes] == [True, False, True, True]
    failed = outcomes[1]
    assert failed.error.kind == "input" and failed.error.line == 3
    assert "row has 3 fields but the header has 4" in failed.error.message
    for o in outcomes:
        if o.ok:
            alone = tire_gap.diagnose(o.name, **OPTIONS)
            assert o.report.to_json() == alone.to_json()
            assert o.report.params() == alone.params()
    assert len(workers) == 2, "both workers took programmes"


def test_diagnose_many_takes_a_scheduler_address(batch):
    from distributed import LocalCluster

    _, programmes = batch
    with LocalCluster(n_workers=1, threads_per_worker=1, dashboard_address=None) as cluster:
        outcomes = tire_gap.diagnose_many(
            programmes[:2], client=cluster.scheduler_address, progress=False, **OPTIONS)
    assert [o.ok for o in outcomes] == [True, False]
    assert outcomes[0].report.to_json() == tire_gap.diagnose(programmes[0], **OPTIONS).to_json()


def test_tire_gap_many_command(batch, tmp_path):
    d, _ = batch
    exe = Path(sys.executable).parent / "tire-gap-many"
    p = subprocess.run(
        [str(exe), str(d), "--each", "--workers", "2", "--no-progress", "--stability-draws", "1",
         "--json-dir", str(tmp_path / "json"), "--summary", str(tmp_path / "summary.csv")],
        capture_output=True, text=True, timeout=600,
    )
    assert p.returncode == 3, p.stderr  # one programme failed; the others are reported
    summary = pd.read_csv(tmp_path / "summary.csv")
    assert len(summary) == 4 and summary["ok"].sum() == 3
    assert "corrupt.csv" in p.stderr
    verdicts = dict(zip(summary["programme"].map(lambda s: Path(s).name), summary["verdict"]))
    assert verdicts["tire12.csv"] == "inflation_pressure"
    assert sorted(f.name for f in (tmp_path / "json").iterdir()) == [
        "tire11.csv.json", "tire12.csv.json", "tire13.csv.json"]


def test_output_names_are_unique():
    from tire_gap._many import file_names

    assert file_names(["a/x.csv", "b/x.csv", "c/y.dat", "d e", "programme 5"]) == [
        "001-x.csv", "002-x.csv", "y.dat", "d", "programme"]
