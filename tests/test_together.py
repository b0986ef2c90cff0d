"""Two effects that help only together (thermolimb/workbench/diagnosis/together.py), on the forecast benchmark's
seed-0 calibration log: the plant's two-mass X8 knee with speed losses, copper's coefficient and a lagging
thermistor hidden, two hours of random holds and motions (docs/model-file.md's ``cal.csv``, byte for byte).

This is selection, not robustness: every member of each pair is one of the plant's hidden effects (or, for the
second mass, its structure), and the catalog holds each."""

from dataclasses import replace

import pytest

from thermolimb.plant import NETWORKS, X8_9, PlantEffects, simulate_profile
from thermolimb.workbench.diagnosis import diagnose, together
from thermolimb.workbench.diagnosis.stability import Stability

HIDDEN = ["sensor_noise", "quantisation", "speed_losses", "winding_tempco", "sensor_lag"]


@pytest.fixture(scope="module")
def calibration():
    spec = replace(X8_9, network=NETWORKS["second_order"])
    log = simulate_profile("random", 7200.0, 1.0, ["knee"], [spec], PlantEffects.from_names(HIDDEN), seed=0).log
    return log.series("knee")


def _by_label(d):
    return {c.label: c for c in d.candidates}


def test_speed_losses_and_the_housing_help_together_where_each_alone_does_not_carry(calibration):
    """Alone, speed losses lower the held-out error by 15 % but are taken in 6 of 10 replicates, and the second
    mass raises it: the walk stopped at Jorgensen et al.'s model. Together they take it from 5.169 to 0.931 K, in
    10 of 10 replicates, and the step is recommended."""
    d = diagnose([calibration], stability=Stability())
    c = _by_label(d)
    pair = c["+ speed_losses with second_node"]
    assert d.recommended is pair and pair.selection_frequency == 1.0
    assert pair.model == ("joule", "effort_bias", "speed_losses", "second_node")
    assert c["+ speed_losses"].unstable_because is not None and not c["+ second_node"].helps
    assert pair.rmse_K <= 0.9 * min(c["+ speed_losses"].rmse_K, c["+ second_node"].rmse_K)
    assert pair.evidence.startswith(f"together: + speed_losses alone {c['+ speed_losses'].rmse_K:.3f} K")
    assert "alone" in d.stability  # the first check, of the changes alone, is kept beside the one that decided
    assert d.stability["alone"]["frequencies"]["+ speed_losses"] == 0.6 == c["+ speed_losses"].selection_frequency
    assert c["+ speed_losses"].evidence.count("Taken in 6 of 10 replicates") == 1


def test_the_lagging_sensor_and_copper_s_coefficient_reach_the_floor_together(calibration):
    """At the end of the walk (the mass, speed losses and the friction on the housing: 0.335 K held out), the
    sensor's lag and copper's coefficient each fail alone; together they reach the readings' floor."""
    model = "joule,effort_bias,speed_losses,second_node,housing_friction"
    d = diagnose([calibration], model=model)
    c = _by_label(d)
    pair = c["+ sensor_lag with winding_tempco"]
    assert d.recommended is pair
    assert not c["+ sensor_lag"].helps and not c["+ winding_tempco"].helps
    assert pair.rmse_K < 1.2 * d.floor.floor_K < 0.3 * d.base.validation["rmse_K"]


def test_without_pairs_the_step_recommends_nothing(calibration, monkeypatch):
    """The same step with no pair tried (MEMBERS = 0): nothing is recommended, as before pairs."""
    monkeypatch.setattr(together, "MEMBERS", 0)
    d = diagnose([calibration], model="joule,effort_bias,speed_losses,second_node,housing_friction")
    assert d.recommended is None
    assert not any(" with " in c.label and c.effect == "winding_tempco" for c in d.candidates)


def test_a_pair_is_kept_only_if_it_beats_its_better_member_by_the_gate(calibration, monkeypatch):
    """The pair of speed losses and the second mass beats speed losses alone (4.366 K held out) by 79 %: kept at the
    10 % gate, not at a gate of 80 %, though refitted the same."""
    from thermolimb.workbench.diagnosis.split_or_blocks import judging_scheme
    from thermolimb.workbench.validation import Scheme

    d = diagnose([calibration])  # no check: speed losses alone are recommended, and no pair is tried
    assert d.recommended.label == "+ speed_losses" and not any(" with speed" in c.label for c in d.candidates)
    scheme = judging_scheme(Scheme(), [calibration])
    kept = {}
    for gate in (0.1, 0.8):
        monkeypatch.setattr(together, "MIN_IMPROVEMENT", gate)
        refitted = []
        real = together.refit_candidate
        monkeypatch.setattr(together, "refit_candidate", lambda cand, *a: refitted.append(real(cand, *a)) or refitted[-1])
        kept[gate] = together.pairs(d.candidates, d.model, [calibration], scheme, d.base, d.base_bic, frozenset())
        monkeypatch.setattr(together, "refit_candidate", real)
        assert [p.label for p in refitted] == ["+ speed_losses with second_node"] and refitted[0].eligible
    assert [p.label for p in kept[0.1]] == ["+ speed_losses with second_node"] and kept[0.8] == []
    assert 0.2 < kept[0.1][0].rmse_K / _by_label(d)["+ speed_losses"].rmse_K < 0.25


@pytest.mark.slow  # half a minute or more on two cores (the default run stays under ten minutes)
def test_a_pair_is_taken_only_where_every_replicate_takes_it(monkeypatch):
    """Both runs of the UR3's J0 (real), cut as benchmarks/stability.py's first copy cuts them: + speed_losses with
    neighbor_coupling (0.880 -> 0.161 K held out on the whole log) is taken in 9 of 10 replicates. A pair is taken
    only where every replicate takes it: not recommended, shown unstable. At the 0.8 a single change needs, this
    copy took it where the whole log (7 of 10 at the first batch, 15 of 20 in all) did not."""
    import numpy as np

    from thermolimb.data import REAL_LOGS
    from thermolimb.workbench.validation import Scheme

    runs = REAL_LOGS["ur3"].read()[0].runs("J0")
    rng = np.random.default_rng([1, 37])
    cut = [(int(rng.integers(0, 6)), int(rng.integers(0, 6))) for _ in runs]
    scheme = Scheme(split=0.7 + rng.uniform(-0.03, 0.03), phase=rng.uniform(-0.3, 0.3))
    copy = [s.slice(a, s.n - b) for s, (a, b) in zip(runs, cut)]
    d = diagnose(copy, scheme=scheme, stability=Stability(seed=1))
    pair = d.unstable
    assert d.recommended is None and pair.label == "+ speed_losses with neighbor_coupling"
    assert pair.selection_frequency == 0.9 and d.stability["min_frequency"] == 1.0 and pair.status == "unstable"
    monkeypatch.setattr(together, "PAIR_FREQUENCY", 0.8)
    assert diagnose(copy, scheme=scheme, stability=Stability(seed=1)).recommended.label == pair.label


def test_a_pair_is_not_taken_by_the_order_rule():
    """The UR3's J2 (real), fitted on its second run with --discover and judged on its first: the replicates take
    + motion_cooling with sensor_lag in 6 of 10 and a protective-stop channel's form in 4. The order rule
    (stability.in_some_order) would read that as agreeing on adding and take the pair; a pair needs every
    replicate, so the step recommends nothing."""
    from thermolimb.data import REAL_LOGS
    from thermolimb.workbench.validation import Scheme

    runs = REAL_LOGS["ur3"].read()[0].runs("J2")
    d = diagnose([runs[1]], discover=True, stability=Stability(), scheme=Scheme.on_runs([runs[0]]))
    pair = _by_label(d)["+ motion_cooling with sensor_lag"]
    assert d.recommended is None and d.unstable is pair and pair.selection_frequency == 0.6
    assert "they agree on adding" not in pair.evidence and "not recommended" in pair.evidence
    assert "a pair is taken only where every replicate takes it. Taken in 6 of 10" in pair.evidence


def test_a_pair_is_judged_only_where_each_member_s_channel_moves(holds_log):
    """A replicate judges a pair it did not build itself; where one member rides a channel that does not move there,
    the pair is not judged, as that member alone is not. On a log of holds whose joint moves in two samples (as in
    a step test), + speed_losses alone is not judged for its velocity, and neither is + speed_losses with
    second_node (before, only the second member's channel was looked at, and the second mass rides none)."""
    from thermolimb.workbench.diagnosis.candidates import Candidate
    from thermolimb.workbench.diagnosis.screen import unexcited

    s = holds_log.series("knee")
    velocity = s.signals.velocity.copy()
    velocity[[1000, 1001]] = 2.0
    d = diagnose([replace(s, signals=replace(s.signals, velocity=velocity))])
    alone = _by_label(d)["+ speed_losses"]
    pair = Candidate("second_node", d.model + ("speed_losses", "second_node"), brings=("speed_losses",))
    pair = unexcited(pair, d.base)
    assert pair.label == "+ speed_losses with second_node" and "velocity is away from rest in 2 of" in alone.unexcited
    assert pair.unexcited == alone.unexcited and pair.evidence == f"not judged: {alone.unexcited}."
