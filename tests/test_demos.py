"""Every registered demo runs in quick mode and writes plots and a summary; the report shows them."""

import json
import re

import pytest
from captions import broken_promises, code_names
from mcap.reader import make_reader
from PIL import Image

from thermolimb.demo_registry import caption, load_demos, run_demo
from thermolimb.plotting.inventory import read_inventory
from thermolimb.report import build_report
from thermolimb.util.errors import UsageError

DEMOS = sorted(load_demos())
COLUMN_PX = 1288


@pytest.fixture(scope="module")
def quick_runs(tmp_path_factory):
    """Each demo runs once in quick mode, into one folder; every test below reads that run."""
    return tmp_path_factory.mktemp("demos"), {}


def quick(quick_runs, name: str) -> dict:
    out, done = quick_runs
    if name not in done:
        done[name] = run_demo(name, out, quick=True, quiet=True)
    return done[name]


# a minute or more each, or near it with nothing else here reading their results (strategies 63 s, ppo-agent 44 s,
# hexapod-walk 78 s on two cores): slow, so that the default run stays well under ten minutes
LONG = ("hexapod-endurance", "humanoid-recovery", "humanoid-switching-map", "strategies", "ppo-agent", "hexapod-walk")


@pytest.mark.parametrize("name", [pytest.param(n, marks=pytest.mark.slow) if n in LONG else n for n in DEMOS])
def test_demo_quick(name, quick_runs):
    summary = quick(quick_runs, name)
    out = quick_runs[0]
    folder = out / name
    assert json.loads((folder / "summary.json").read_text()) == summary
    assert list(folder.glob("*.png"))
    page = build_report(out).read_text()
    assert f"id='{name}'" in page and ".png" in page
    section = page.split(f"<h2 id='{name}'>")[1].split("<h2 id=")[0]
    assert "class='missing'" not in section, section[:500]  # the headline was built from what the demo wrote
    values = re.findall(r"<td class='value'>([^<]*)</td>", section)
    assert values and all(v.strip() for v in values), values  # a headline table with rows, every value given
    for src in re.findall(r"<img src='([^']+)'", section):
        assert (out / src).is_file(), src  # every figure the section shows exists
        with Image.open(out / src) as image:  # and fits the report's column unscaled (1320 px less its padding)
            assert image.width <= COLUMN_PX, (src, image.width)


@pytest.mark.slow  # every demo's figures, the long ones included
def test_every_figure_keeps_its_captions_promise(quick_runs):
    """What a caption tells the reader (a dashed 75 °C line, error bars, the measurement in black) is drawn, and
    no axis is labelled with a raw identifier; read from each PNG's own inventory of what it draws."""
    out = quick_runs[0]
    demos = load_demos()
    problems, checked = [], 0
    for name in DEMOS:
        quick(quick_runs, name)
        for png in sorted((out / name).glob("*.png")):
            axes = read_inventory(png)
            assert axes is not None, f"{png.name} was not written through thermolimb.plotting.fits.save"
            text = caption(demos[name].page, png.name)
            problems += [f"{name}/{png.name}: {p}" for p in broken_promises(text, axes) + code_names(axes)]
            checked += 1
    assert checked >= 20, checked
    assert not problems, "\n".join(problems)


def test_thermal_fit_demo_predicts_the_squats(quick_runs):
    summary = quick(quick_runs, "thermal-fit")
    for channel, methods in summary["channels"].items():
        # output error predicts the 90-minute squat experiment from effort alone
        assert methods["output_error"]["prediction"]["fit_percent"] > 70.0, channel
        assert (methods["output_error"]["prediction"]["rmse_K"]
                <= methods["jorgensen_gd"]["prediction"]["rmse_K"] + 1e-9), channel


@pytest.mark.slow  # the hexapod's walk (LONG)
def test_specified_summaries_keep_their_shape(quick_runs):
    """Issues 4 and 5 give summary.json's exact keys; anything else goes to details.json."""
    walk = quick(quick_runs, "hexapod-walk")
    assert set(walk) == {"walk_0kg", "walk_2kg", "stand_5kg"}
    for scenario in walk.values():
        assert set(scenario) == {"vertical_only", "minimax", "minimax_lex", "thermal_aware"}
        for record in scenario.values():
            assert {"peak_norm_torque", "mean_norm_torque", "max_temperature_C", "time_to_limit_s"} <= set(record)
    assert json.loads((quick_runs[0] / "hexapod-walk" / "details.json").read_text())["duration_s"] == 15.0


def test_report_without_results_says_what_to_run(tmp_path):
    with pytest.raises(UsageError, match="thermolimb demo all"):
        build_report(tmp_path)
    (tmp_path / "fit").mkdir()
    (tmp_path / "fit" / "summary.json").write_text("[1, 2]")
    with pytest.raises(UsageError, match="summary.json holds list, not a demo's summary"):
        build_report(tmp_path)


def test_diagnose_demo_finds_both_hidden_effects(quick_runs):
    summary = quick(quick_runs, "diagnose")
    assert summary["found"] == sorted(summary["hidden_effects"])
    assert summary["diagnosis"]["auto"][-1]["rmse_K"] < 0.1


def test_custom_effect_is_ranked_like_a_builtin_and_then_unregistered(quick_runs):
    """The user's power law is not the plant's law: it must beat the catalog's speed losses, and the physics
    itself (current squared, once current is logged) must beat it."""
    from thermolimb.model import TERMS

    summary = quick(quick_runs, "custom-effect")
    user = summary["with_user_effect"]
    assert any(step["change"] == "+ speed_power_heating" for step in user)
    assert user[-1]["rmse_K"] < 0.5 * summary["catalog_only"][-1]["rmse_K"]
    assert summary["with_current_logged"][-1]["rmse_K"] < user[-1]["rmse_K"]
    assert "speed_power_heating" not in TERMS


def test_discovery_demo_names_the_brake_and_writes_a_term_file(quick_runs):
    """The brake's heat is found from its channel with the plant's value (3 W through 3.256 K/W), the walk ends
    well below the catalog's, and the term file the report shows compiles."""
    summary = quick(quick_runs, "discovery")
    assert any(step["change"].startswith("+ brake_heat") for step in summary["with_discovery"])
    assert summary["generated_params"]["brake_heat_K"]["value"] == pytest.approx(3.0 * 3.256, rel=0.1)
    assert summary["with_discovery"][-1]["rmse_K"] < 0.2 * summary["catalog_only"][-1]["rmse_K"]
    source = (quick_runs[0] / "discovery" / summary["term_file"]).read_text()
    compile(source, summary["term_file"], "exec")
    assert "brake_heat_K =" in source


def test_real_pmsm_data_points_to_current_heating(quick_runs):
    summary = quick(quick_runs, "pmsm-real-data")
    for name, entry in summary["profiles"].items():
        waterfall = entry["default"]["waterfall"]  # from the default start, narrowed to what the torque's levels pin:
        # profile 24 holds it at two (rest and 64 N m), which cannot tell Joule heating from the effort bias
        assert waterfall[0]["model"] == (["joule"] if name == "profile24" else ["joule", "effort_bias"]), name
        # the current's heat is taken, or shown as the change that helps but is not stable enough to take
        # (profile 46: the swap in 6 of 10 replicates, dropping the bias in 3)
        last = waterfall[-1]
        assert ("current_heating" in last["model"] and "joule" not in last["model"]) or \
            "current_heating" in last.get("unstable", {}).get("change", ""), name
        assert last["rmse_K"] < 0.5 * waterfall[0]["rmse_K"], name
    assert "speed_losses" in summary["profiles"]["profile46"]["default"]["waterfall"][-1]["model"]
    # profile 24's last 30 % holds one torque and one current: judged on blocks, one holding its release
    assert "holds the heat input still" in summary["profiles"]["profile24"]["default"]["scheme"]
    cv = summary["profiles"]["profile24"]["cv4"]["waterfall"]
    assert "current_heating" in cv[-1]["model"] and cv[-1]["rmse_K"] < 0.5 * cv[0]["rmse_K"]


def test_real_logs_demo_runs_the_loop_on_every_bundled_log(quick_runs):
    summary = quick(quick_runs, "real-logs")
    assert set(summary) == {"ur3", "wx200", "bldc"}
    for entry in summary.values():
        for record in entry["actuators"].values():
            walk = record["split"]
            assert walk["steps"][0]["change"] == "start" and walk["after_K"] <= walk["before_K"]
    j3 = summary["ur3"]["actuators"]["J3"]["split"]  # a wrist joint: heat from its neighbours
    assert "neighbor_coupling" in j3["final_model"] and j3["after_K"] < 0.5 * j3["before_K"]


@pytest.mark.slow
def test_endurance_summary_has_the_cells_the_issue_names(quick_runs):
    cells = quick(quick_runs, "hexapod-endurance")["cells"]
    assert {c["mode"] for c in cells} == {"walk", "stand"}
    for c in cells:
        assert set(c) == {"payload_kg", "ambient_C", "mode", "strategy", "time_to_derate_s", "horizon_s",
                          "distance_per_s_m"}
        assert c["time_to_derate_s"] is None or 0 < c["time_to_derate_s"] <= c["horizon_s"]
    stand = {c["strategy"]: c for c in cells if c["mode"] == "stand" and c["payload_kg"] == 80.0}
    # standing with 80 kg at 40 degC vertical forces derate within the hour; the planned stance lasts twice as long
    assert stand["vertical_only"]["time_to_derate_s"] < 3600.0
    planned = stand["thermal_gait"]["time_to_derate_s"]
    assert planned is None or planned >= 2 * stand["vertical_only"]["time_to_derate_s"]


def test_forecast_demo_saves_forecasts_and_monitors(quick_runs):
    summary = quick(quick_runs, "forecast")
    folder = quick_runs[0] / "forecast"
    assert (folder / "model_auto.json").is_file()
    with open(folder / "monitor.mcap", "rb") as f:  # a complete recording (a summary at its end), with messages in it
        stats = make_reader(f).get_summary().statistics
    assert stats.message_count > 100, stats
    auto, default = summary["coverage"]["auto"], summary["coverage"]["default"]
    # the model the workbench finds answers better than Jorgensen et al.'s on a plant richer than both
    assert auto["median_error"] < 0.5 * default["median_error"]
    assert auto["covered"] >= 0.75 * auto["cases"]
    m = summary["monitor"]
    assert m["publications"] >= 1000 and m["rmse_K"] <= 1.01 * m["thermistor_rmse_K"]  # it follows the whole walk


def test_the_forecast_demo_s_monitor_band_holds_the_true_winding(quick_runs):
    m = quick(quick_runs, "forecast")["monitor"]
    assert m["rmse_K"] < m["thermistor_rmse_K"] and m["true_within_2sd"] > 0.8


def test_next_experiment_demo_sizes_what_the_short_log_could_not(quick_runs):
    """The planned test sizes the housing's time constant the 10-minute log left at ± hundreds of seconds, within
    1.5 times the standard error the plan promised, and the plant's true winding stays under the 90 degC limit."""
    summary = quick(quick_runs, "next-experiment")
    assert summary["before"]["relative"] > 0.2 and summary["after"]["relative"] < 0.01
    assert 1 / 1.5 <= summary["obtained_over_promised"] <= 1.5
    assert summary["hottest_true_C"] < 90.0 and summary["peak_effort_Nm"] <= 20.0
