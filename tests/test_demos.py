"""Every registered demo runs in quick mode and writes plots and a summary; the report shows them."""

import json

import pytest

from thermolimb.demo_registry import load_demos, run_demo
from thermolimb.errors import UsageError
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
    with pytest.raises(UsageError, match="thermolimb demo all"):
        build_report(tmp_path)


def test_diagnose_demo_finds_both_hidden_effects(tmp_path):
    summary = run_demo("diagnose", tmp_path, quick=True, quiet=True)
    assert summary["found"] == sorted(summary["hidden_effects"])
    assert summary["diagnosis"]["auto"][-1]["rmse_K"] < 0.1


def test_custom_effect_is_ranked_like_a_builtin_and_then_unregistered(tmp_path):
    """The user's power law is not the plant's law: it must beat the catalog's speed losses, and the physics
    itself (current squared, once current is logged) must beat it."""
    from thermolimb.model import TERMS

    summary = run_demo("custom-effect", tmp_path, quick=True, quiet=True)
    user = summary["with_user_effect"]
    assert any(step["change"] == "+ speed_power_heating" for step in user)
    assert user[-1]["rmse_K"] < 0.5 * summary["catalog_only"][-1]["rmse_K"]
    assert summary["with_current_logged"][-1]["rmse_K"] < user[-1]["rmse_K"]
    assert "speed_power_heating" not in TERMS


def test_real_pmsm_data_points_to_current_heating(tmp_path):
    summary = run_demo("pmsm-real-data", tmp_path, quick=True, quiet=True)
    for name, entry in summary["profiles"].items():
        waterfall = entry["split"]["waterfall"]  # from the default start
        assert waterfall[0]["model"] == ["joule", "effort_bias"]
        assert "current_heating" in waterfall[-1]["model"] and "joule" not in waterfall[-1]["model"], name
        assert waterfall[-1]["rmse_K"] < 0.5 * waterfall[0]["rmse_K"], name
    assert "speed_losses" in summary["profiles"]["profile46"]["split"]["waterfall"][-1]["model"]
    cv = summary["profiles"]["profile24"]["cv4"]["waterfall"]
    assert "current_heating" in cv[-1]["model"] and cv[-1]["rmse_K"] < 0.5 * cv[0]["rmse_K"]
