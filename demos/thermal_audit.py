"""Demo ``thermal-audit``: will a controller overheat a joint? Gymnasium's MuJoCo humanoid standing still.

``Humanoid-v5`` (extra ``mujoco``), never ended for being unhealthy, is held at its initial pose by a joint-space
PD controller -- stiff, then compliant -- wrapped with :class:`thermolimb.envs.ThermalWrapper`: every joint heated
from the torque MuJoCo applies, by the suite's plant with the humanoid's knee actuator (``humanoid_pb``'s
Valkyrie-like knee: a 40 s winding on a slow housing, a 105 degC winding limit) at every joint.  The audit says,
per joint, the peak temperature and when it reached its limit, and which joint limits the run.  It is the
question learned whole-body controllers raise on hardware (ankles or hips at their warning within minutes while
standing), asked in simulation.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from humanoid_pb.constants import ACTUATORS
from humanoid_pb.thermal import actuator_specs
from thermolimb.demo_registry import DemoPage, demo_main, register_demo

NAME = "thermal-audit"
ENV_ID = "Humanoid-v5"
ENV_KWARGS = {"terminate_when_unhealthy": False, "reset_noise_scale": 0.0}
CONTROLLERS = {"stiff": (300.0, 10.0), "compliant": (30.0, 3.0)}  # joint-space PD gains: N m/rad, N m s/rad


class HoldPose:
    """Joint-space PD towards the pose the episode started in, as MuJoCo's controls (torque over gear, clipped)."""

    def __init__(self, name: str, kp: float, kd: float):
        self.__name__, self.kp, self.kd = name, kp, kd
        self.q0 = None

    def __call__(self, env, observation):
        u = env.unwrapped
        m, d = u.model, u.data
        joint = m.actuator_trnid[:, 0]
        qadr, vadr = m.jnt_qposadr[joint], m.jnt_dofadr[joint]
        if self.q0 is None or d.time == 0.0:
            self.q0 = d.qpos[qadr].copy()
        torque = self.kp * (self.q0 - d.qpos[qadr]) - self.kd * d.qvel[vadr]
        low, high = m.actuator_ctrlrange.T
        return np.clip(torque / m.actuator_gear[:, 0], low, high).astype(np.float32)


# the two controllers as policies the command line can name: thermolimb audit --policy thermolimb_demos.thermal_audit:stiff
stiff = HoldPose("stiff PD (kp 300 N m/rad)", *CONTROLLERS["stiff"])
compliant = HoldPose("compliant PD (kp 30 N m/rad)", *CONTROLLERS["compliant"])


def knee_spec():
    return actuator_specs()[next(i for i, a in enumerate(ACTUATORS) if a.endswith("knee"))]


def _headline(summary: dict) -> list[tuple[str, str, str]]:
    rows = []
    for name, r in summary["audits"].items():
        top = max(r["joints"], key=lambda j: j["peak_C"])
        first = [j for j in r["joints"] if j["time_to_limit_s"] is not None]
        when = (f"{min(j['time_to_limit_s'] for j in first):.0f} s" if first else f"not within {r['duration_s']:.0f} s")
        rows.append((f"{name} controller: limiting joint", f"{r['limiting_joint']} (peak {top['peak_C']:.1f} degC)",
                     f"first joint at its {top['limit_C']:.0f} degC limit: {when}"))
    return rows


def _finding(summary: dict) -> str:
    stiff, compliant = summary["audits"]["stiff"], summary["audits"]["compliant"]

    def peak(r):
        return max(j["peak_C"] for j in r["joints"])

    reached = [j["joint"] for j in stiff["joints"] if j["time_to_limit_s"] is not None]
    return (f"Standing still for {stiff['duration_s']:.0f} s, the stiff controller heats {stiff['limiting_joint']} to "
            f"{peak(stiff):.1f} degC" + (f" ({len(reached)} joints reach their limit)" if reached else "") +
            f"; the compliant one's hottest joint ({compliant['limiting_joint']}) reaches {peak(compliant):.1f} degC.")


PAGE = DemoPage(
    about="A thermal audit in Gymnasium's MuJoCo humanoid (Humanoid-v5): the same standing task under a stiff and a "
          "compliant joint-space PD controller, each joint heated from the torque MuJoCo applies by the suite's plant "
          "with a Valkyrie-like knee actuator at every joint (thermolimb audit, thermolimb.envs.ThermalWrapper). "
          "Look at which joints heat and how fast: stiffness holds the pose with torque, and torque is heat.",
    headline=_headline,
    finding=_finding,
    captions={"audit_stiff.png": "Every joint's winding temperature under the stiff controller; the limiting joint "
                                 "bold, the limit dashed.",
              "audit_compliant.png": "The same under the compliant controller."})


@register_demo(NAME, "a thermal audit of two controllers in Gymnasium's MuJoCo humanoid (extra 'mujoco')",
               requires=("mujoco",), page=PAGE, extra="mujoco", cost_s=12)
def run(out: Path, quick: bool = False, quiet: bool = True) -> dict:
    from thermolimb.envs.audit import audit
    from thermolimb.plotting.audit import plot_audit

    duration_s = 60.0 if quick else 600.0
    spec = knee_spec()
    audits = {}
    for name, (kp, kd) in CONTROLLERS.items():
        result = audit(ENV_ID, HoldPose(f"{name} PD (kp {kp:g} N m/rad)", kp, kd), duration_s, seed=0,
                       env_kwargs=ENV_KWARGS, plant=spec)
        plot_audit(result, out / f"audit_{name}.png")
        audits[name] = result.to_json()
    return {"env": ENV_ID, "duration_s": duration_s, "actuator": spec.model, "winding_limit_C": spec.winding_limit_C,
            "gains": {k: {"kp_Nm_per_rad": v[0], "kd_Nm_s_per_rad": v[1]} for k, v in CONTROLLERS.items()},
            "audits": audits}


def main(argv=None) -> dict:
    return demo_main(NAME, argv)


if __name__ == "__main__":
    main()
