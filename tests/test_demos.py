"""Every registered demo runs in quick mode and writes plots and a summary; the report shows them."""

import json

import pytest

from thermolimb.demo_registry import load_demos, run_demo
from thermolimb.report import build_report

DEMOS = sorted(load_demos())


@pytest.mark.parametrize("name", DEMOS)
def test_demo_quick(name, tmp_path):
    summary = run_demo(name, tmp_path, quick=True, quiet=True)
    folder = tmp_path / name
    assert json.loads((folder / "summary.json").read_text()) == summary
    assert list(folder.glob("*.png"))
    index = build_report(tmp_path)
    page = index.read_text()
    assert f"id='{name}'" in page and ".png" in page


def test_thermal_fit_demo_predicts_the_squats(tmp_path):
    summary = run_demo("thermal-fit", tmp_path, quick=True, quiet=True)
    for channel, methods in summary["channels"].items():
        # output error predicts the 90-minute squat experiment from effort alone
        assert methods["output_error"]["prediction"]["fit_percent"] > 70.0, channel
        assert (methods["output_error"]["prediction"]["rmse_K"]
                <= methods["seed_gd"]["prediction"]["rmse_K"] + 1e-9), channel


def test_report_without_results_says_what_to_run(tmp_path):
    with pytest.raises(FileNotFoundError, match="thermolimb demo all"):
        build_report(tmp_path)
