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


def test_specified_summaries_keep_their_shape(tmp_path):
    """Issues 4 and 5 give summary.json's exact keys; anything else goes to details.json."""
    walk = run_demo("hexapod-walk", tmp_path, quick=True, quiet=True)
    assert set(walk) == {"walk_0kg", "walk_2kg", "stand_5kg"}
    for scenario in walk.values():
        assert set(scenario) == {"vertical_only", "minimax", "minimax_lex", "thermal_aware"}
        for record in scenario.values():
            assert {"peak_norm_torque", "mean_norm_torque", "max_temperature_C", "time_to_limit_s"} <= set(record)
    assert json.loads((tmp_path / "hexapod-walk" / "details.json").read_text())["duration_s"] == 15.0


def test_report_without_results_says_what_to_run(tmp_path):
    with pytest.raises(FileNotFoundError, match="thermolimb demo all"):
        build_report(tmp_path)


def test_diagnose_demo_finds_both_hidden_effects(tmp_path):
    summary = run_demo("diagnose", tmp_path, quick=True, quiet=True)
    assert summary["found"] == sorted(summary["hidden_effects"])
    assert summary["diagnosis"]["auto"][-1]["rmse_K"] < 0.1


def test_custom_effect_is_ranked_like_a_builtin_and_then_unregistered(tmp_path):
    from thermolimb.model import TERMS

    summary = run_demo("custom-effect", tmp_path, quick=True, quiet=True)
    assert summary["catalog_only"]["recommended"] != "field_weakening_speed"
    after = summary["with_user_effect"]
    assert after["recommended"] == "field_weakening_speed"
    assert after["candidates"][0]["rmse_K"] < 0.5 * summary["catalog_only"]["candidates"][0]["rmse_K"]
    assert "field_weakening_speed" not in TERMS


def test_real_pmsm_data_points_to_current_heating(tmp_path):
    summary = run_demo("pmsm-real-data", tmp_path, quick=True, quiet=True)
    for name, entry in summary["profiles"].items():
        waterfall = entry["split"]["waterfall"]
        assert "current_heating" in waterfall[1]["model"], name
        assert waterfall[-1]["rmse_K"] < 0.5 * waterfall[0]["rmse_K"], name
    assert "current_heating" in summary["profiles"]["profile24"]["cv4"]["recommended_model"]
