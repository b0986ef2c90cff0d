"""An identified model in MuJoCo: the thermal state of a ``<dcmotor>`` actuator (MuJoCo 3.7 and later).

MuJoCo's ``thermal = "resistance capacitance timeconst tempcoef reftemp ambient"`` (K/W, J/K, s, 1/K, degC,
degC) gives the winding one thermal mass heated by the motor current, ``tau dx/dt = R_th i^2 R_e (1 + a (T -
T_ref)) - x`` with ``x = T - ambient`` (the actuator's activation) and ``i`` the current its torque needs.
Jorgensen et al.'s first-order model reads ``RC dT/dt = T_offset + beta R F^2 - T`` on the effort ``F`` logged
at the joint, so:

* ``timeconst`` is ``RC_s``; ``ambient`` is ``T_offset_C``;
* the heat gain maps through the motor: a joint torque ``F = G K i`` (gear ``G``, motor constant ``K``), so
  ``R_th = beta R (G K)^2 / R_e``; where the logged effort is the current itself (unit ``A``), ``R_th = beta R
  / R_e``; ``capacitance`` is ``timeconst / R_th``;
* copper's coefficient (``winding_tempco``) is ``tempcoef`` at ``reftemp`` = 25 degC -- with a difference said
  in the snippet: MuJoCo's dcmotor is driven by a voltage, so a warmer winding there draws less current and
  gives less torque for the same command, where the identified model (a current-controlled drive) keeps the
  torque and heats more.

What MuJoCo's one-node state cannot hold -- a second mass, an effort bias, a lagging sensor, speed losses,
anything else -- is dropped and said, with what dropping it costs on a log (:func:`cost_of_dropping`); on that
log the one node can be fitted again without them (:func:`refitted`, ``export --refit``).  The check
(:func:`run_in_mujoco`): the exported actuator, driven in MuJoCo by a log's torque with its rotor held,
against this suite's free run of the same (exported) model; ``benchmarks/travel.py`` prints the difference.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from xml.sax.saxutils import quoteattr

import numpy as np

from .constants import COPPER_REFERENCE_C
from .identification import FreeRunLeastSquares
from .model.model import ThermalModel, model_parameters
from .model.saved import SavedModel
from .model.signals import Signals
from .model.terms import TERMS
from .util.errors import ThermolimbError, UsageError

TORQUE_UNITS = ("N m", "Nm", "N·m", "N.m")
CURRENT_UNITS = ("A",)
NIL = 1e-6  # a heat gain under this share of its standard error is nil (at its bound): said
CHECK_SUBSTEPS = 20  # MuJoCo steps per log interval in the check (its act integration is explicit)


@dataclass(frozen=True)
class Motor:
    """The motor behind the joint: torque constant (N m/A), terminal resistance (ohm), gear ratio."""

    motor_const: float
    resistance_ohm: float
    gear: float = 1.0

    def __post_init__(self):
        for name, value in (("--motor-const", self.motor_const), ("--resistance", self.resistance_ohm),
                            ("--gear", self.gear)):
            if not np.isfinite(value) or value <= 0:
                raise UsageError(f"{name} must be a positive number, got {value!r}")


@dataclass(frozen=True)
class DcMotorThermal:
    """One actuator's ``<dcmotor>`` thermal attributes, and what the model had that they do not hold."""

    actuator: str
    motor: Motor
    resistance_K_per_W: float
    capacitance_J_per_K: float
    timeconst_s: float
    tempcoef_per_K: float
    reftemp_C: float
    ambient_C: float
    exported: ThermalModel  # the model MuJoCo's state reproduces (the saved one without what is dropped)
    dropped: tuple[str, ...] = ()
    notes: tuple[str, ...] = field(default=())
    current: bool = False  # the model heats from the current (its effort in A, or a current channel)

    def motor_torque(self, signals: Signals) -> np.ndarray:
        """What MuJoCo's actuator is commanded, from a log's channels: the joint torque over the gear, or the
        current times the motor constant."""
        if self.current:
            source = next(TERMS[t] for t in self.exported.terms if TERMS[t].squared_channel)
            current = signals.current_A if source.squared_channel == "current" else signals.effort
            return np.asarray(current, float) * self.motor.motor_const
        return np.asarray(signals.effort, float) / self.motor.gear

    @property
    def thermal(self) -> tuple[float, ...]:
        """The six numbers of ``thermal=""`` (MuJoCo derives the capacitance from the other two: given as
        0)."""
        return (
            self.resistance_K_per_W,
            0.0,
            self.timeconst_s,
            self.tempcoef_per_K,
            self.reftemp_C,
            self.ambient_C,
        )

    def element(self, joint: str | None = None) -> str:
        """The ``<dcmotor>`` element, torque-commanded (``input="ff"``: the torque is delivered as
        commanded)."""
        thermal = " ".join(f"{v:.9g}" for v in self.thermal)
        m = self.motor
        return (f'<dcmotor name={quoteattr(self.actuator)} joint={quoteattr(joint or self.actuator)} '
                f'gear="{m.gear:.9g}" motorconst="{m.motor_const:.9g}" resistance="{m.resistance_ohm:.9g}" '
                f'input="ff" thermal="{thermal}"/>')


def to_dcmotor(saved: SavedModel, motor: Motor) -> DcMotorThermal:
    """Map one saved model onto a dcmotor's thermal state (module docstring); what does not map is dropped,
    said."""
    model, p = saved.model, saved.model.params
    # the Joule heat (from the effort's square first, else the current's) is what a dcmotor's I^2 R can carry
    joules = sorted((t for t in model.terms if TERMS[t].squared_channel),
                    key=lambda t: TERMS[t].squared_channel != "effort")
    if not joules:
        raise UsageError(f"{saved.actuator}: the model ({','.join(model.terms)}) "
                         "has no Joule heating (from effort or "
                         f"current); MuJoCo's dcmotor heats only by its current")
    source = joules[0]
    name = TERMS[source].parameters[0].name
    unit = "A" if TERMS[source].squared_channel == "current" else saved.channel_units.get("effort", "N m")
    gain = p[name]
    if unit in TORQUE_UNITS:
        r_th = gain * (motor.gear * motor.motor_const) ** 2 / motor.resistance_ohm
    elif unit in CURRENT_UNITS:
        r_th = gain / motor.resistance_ohm
    else:
        raise UsageError(f"{saved.actuator}: the model's effort is in "
                         f"{unit!r}; export maps a joint torque (N m) or "
                         f"the motor current (A) onto MuJoCo's dcmotor")
    if not r_th > 0:
        raise UsageError(f"{saved.actuator}: the model's Joule heating "
                         "is zero; there is no heat for MuJoCo's thermal "
                         f"state to carry")
    # copper's coefficient is the dcmotor's tempcoef; every other term has no place in its one node
    copper = next((t for t in model.terms if TERMS[t].scales_resistance), None)
    kept = (source,) + ((copper,) if copper else ())
    names = {q.name for q in model_parameters(kept)}
    exported = ThermalModel(kept, {k: v for k, v in p.items() if k in names})
    tempcoef = p[TERMS[copper].parameters[0].name] if copper else 0.0
    notes = []
    if tempcoef:
        notes.append("copper's coefficient is exported; MuJoCo's dcmotor "
                     "is voltage-driven, so there a warmer winding "
                     "draws less current and gives less torque for "
                     "the same command, where the identified model (a "
                     "current-controlled drive) keeps the torque and heats more")
    if unit in CURRENT_UNITS:
        notes.append("the model's heat is from the motor current: in "
                     "MuJoCo that is the torque over the motor constant")
    se = float(saved.stderr.get(name, 0.0))
    if gain < NIL * se:  # the UR3's J5: its heat is its bias's, 1.3e-16 +- 6.1 K/A^2 from the current squared
        notes.append(f"its heat gain is nil ({name} = {gain:.2g} ± "
                     f"{se:.2g} {saved.units.get(name, '')}, at its "
                     "bound): MuJoCo's node will not heat this joint; "
                     "what warmed it on the log was another term "
                     f"or the log's drift")
    return DcMotorThermal(saved.actuator, motor, float(r_th), float(p["RC_s"] / r_th), float(p["RC_s"]),
                          float(tempcoef), COPPER_REFERENCE_C, float(p["T_offset_C"]), exported,
                          tuple(t for t in model.terms if t not in kept), tuple(notes),
                          current=unit in CURRENT_UNITS)


EXPORT_MARK = "thermolimb export"  # what the snippet's first comment says: a file export may replace


def commented(text: str) -> str:
    """Text made safe inside an XML comment, which may hold neither ``--`` nor end in ``-``."""
    text = str(text)
    while "--" in text:
        text = text.replace("--", "- -")
    return text + " " if text.endswith("-") else text


def mjcf_snippet(exports: list[DcMotorThermal], joints: dict[str, str] | None = None) -> str:
    """An ``<actuator>`` block of MJCF with each actuator's dcmotor, what was dropped said in comments."""
    lines = [f"<!-- {EXPORT_MARK}: Jorgensen et al.'s first-order model on MuJoCo's dcmotor thermal state",
             "     (thermal = resistance K/W, capacitance J/K (0: "
             "timeconst/resistance), timeconst s, tempcoef 1/K,",
             "      reftemp degC, ambient degC); the winding "
             "temperature is ambient + the actuator's activation -->",
             "<actuator>"]
    for e in exports:
        for term in e.dropped:
            lines.append(f"  <!-- {commented(e.actuator)}: {term} dropped "
                         "(MuJoCo's dcmotor has one thermal node, "
                         f"heated by its current) -->")
        for note in e.notes:
            lines.append(f"  <!-- {commented(e.actuator)}: {commented(note)} -->")
        lines.append("  " + e.element((joints or {}).get(e.actuator)))
    lines.append("</actuator>")
    return "\n".join(lines) + "\n"


def refitted(saved: SavedModel, export: DcMotorThermal, series) -> DcMotorThermal:
    """The one-node model MuJoCo holds (the exported terms: heat source, copper's coefficient where kept,
    ``RC_s``, ``T_offset_C``) fitted again on a log (one actuator's runs), from the exported values, and
    exported: what was dropped then no longer leaves the kept parameters where the whole model had put them
    (the UR3's J1, heat from its current with a bias: 16.7 K RMSE on its log with the bias dropped, 0.041 K
    refitted; docs/travel.md)."""
    fit = FreeRunLeastSquares(model=export.exported.terms, initial=dict(export.exported.params)).fit(series)
    again = to_dcmotor(replace(saved, model=fit.model_, stderr=fit.stderr_), export.motor)
    return replace(again, dropped=export.dropped,
                   notes=again.notes + ("refitted on the log without what was dropped (one thermal node)",))


def cost_of_dropping(saved: SavedModel, export: DcMotorThermal, series) -> dict:
    """On a log (one actuator's runs): the saved model's and the exported model's free-run RMSE against the
    readings (K), and between the two."""
    full, reduced, measured = [], [], []
    for s in series:
        full.append(saved.model.free_run(s))
        reduced.append(export.exported.free_run(s))
        measured.append(s.temperature_C)
    full, reduced, measured = (np.concatenate(x) for x in (full, reduced, measured))

    def rmse(a, b):
        return float(np.sqrt(np.mean((a - b) ** 2)))

    return {"saved_rmse_K": rmse(full, measured), "exported_rmse_K": rmse(reduced, measured),
            "between_K": rmse(full, reduced), "samples": int(measured.size)}


def run_in_mujoco(export: DcMotorThermal, signals: Signals, start_C: float,
                  substeps: int = CHECK_SUBSTEPS) -> np.ndarray:
    """The winding temperature (degC) at each sample of ``signals``, integrated by MuJoCo itself: one hinge
    joint, held still by an equality constraint, driven through the exported dcmotor by the log's effort
    (zero-order hold over each interval, as the suite's exact simulation holds it)."""
    import mujoco  # the optional extra 'mujoco'

    dt = np.diff(signals.time_s)
    timestep = float(np.min(dt)) / substeps
    xml = (f'<mujoco><option timestep="{timestep:.12g}" integrator="Euler"/><worldbody><body>'
           f'<joint name="j" type="hinge"/><geom size=".05" mass="1"/></body></worldbody>'
           f'<equality><joint joint1="j" polycoef="0 0 0 0 0"/></equality>'
           f'<actuator>{export.element("j")}</actuator></mujoco>')
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    adr = int(model.actuator_actadr[0])
    data.act[adr] = start_C - export.ambient_C
    motor_torque = export.motor_torque(signals)
    out = np.empty(signals.n)
    out[0] = start_C
    for k in range(signals.n - 1):
        data.ctrl[0] = motor_torque[k]
        steps = max(1, int(round(dt[k] / timestep)))
        model.opt.timestep = dt[k] / steps
        for _ in range(steps):
            mujoco.mj_step(model, data)
        out[k + 1] = export.ambient_C + data.act[adr]
    return out


THERMAL_FIELDS = ("resistance_K_per_W", "capacitance_J_per_K", "timeconst_s", "tempcoef_per_K", "reftemp_C",
                  "ambient_C")


def exported(saved: SavedModel, motor: Motor, series=(), refit: bool = False) -> tuple[DcMotorThermal, dict]:
    """One actuator's export and its record (what ``thermolimb export --json`` prints): the dcmotor's
    thermal attributes, what was dropped, the notes; with ``series`` (the actuator's runs of its calibration
    log, in the model's units), what dropping costs on the log (:func:`cost_of_dropping`), the one node fitted
    again there (:func:`refitted`; exported in place of the saved model without the dropped terms with
    ``refit``), and MuJoCo's own integration of the export against the suite's free run (``check``; ``None``
    without MuJoCo)."""
    export = to_dcmotor(saved, motor)
    again, failed = None, None
    if series and export.dropped:
        try:
            again = refitted(saved, export, series)
        except ThermolimbError as exc:  # said beside the export; with refit, the export's own error
            if refit:
                raise
            failed = str(exc)
    if again is not None and refit:
        export = again
    record = {"actuator": export.actuator,
              "thermal": {f: getattr(export, f) for f in THERMAL_FIELDS},
              "dropped": list(export.dropped), "notes": list(export.notes)}
    if series:
        record["cost"] = cost_of_dropping(saved, export, series)
        if again is not None:
            cost = record["cost"] if export is again else cost_of_dropping(saved, again, series)
            record["refit"] = {"exported": export is again, "params": dict(again.exported.params),
                               "rmse_K": cost["exported_rmse_K"]}
        elif failed:
            record["refit"] = {"exported": False, "error": failed}
        record["check"] = mujoco_check(export, series[0])
    return export, record


def mujoco_check(export: DcMotorThermal, series) -> dict | None:
    """MuJoCo's integration of the exported actuator against the suite's free run of the same model, on a run
    (``None`` where MuJoCo is not installed)."""
    try:
        mujoco_C = run_in_mujoco(export, series.signals, float(series.temperature_C[0]))
    except ImportError:
        return None
    ours = export.exported.simulate(series.signals, float(series.temperature_C[0]))
    rise = float(ours.max() - ours.min())
    worst = float(abs(mujoco_C - ours).max())
    return {"max_difference_K": worst, "rise_K": rise, "share_of_rise": worst / rise if rise > 0 else None,
            "samples": int(series.n)}
