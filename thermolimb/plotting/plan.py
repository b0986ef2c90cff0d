"""A planned test's figure: the effort set-points (and velocity), then the predicted winding with the upper
end of its 90 % forecast interval, the margin and the limit."""

from __future__ import annotations

from pathlib import Path

from ..util.atomic import file_stem
from .fits import plt, save


def plot_plan(plan, folder: Path) -> Path:
    """``plan``: a :class:`~thermolimb.experiment.Plan`; writes ``plan_<actuator>.png`` into ``folder``."""
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 5.5), sharex=True, height_ratios=(1, 2))
    minutes = plan.time_s / 60.0
    top.step(minutes, plan.effort, where="post", color="tab:blue", label="effort set-point")
    top.set_ylabel(f"effort ({plan.effort_unit or 'unit not given'})")
    if plan.velocity is not None:
        twin = top.twinx()
        twin.step(minutes, plan.velocity, where="post", color="tab:green", lw=0.9, label="velocity set-point")
        twin.set_ylabel("velocity (rad/s)")
    top.legend(loc="upper right", fontsize=7, frameon=False)
    top.grid(alpha=0.3)
    lim = plan.limits
    bottom.plot(minutes, plan.predicted_C, color="tab:red", label="predicted winding")
    bottom.fill_between(minutes, plan.predicted_C, plan.high_C, color="tab:red", alpha=0.2,
                        label="up to the 90 % interval's upper end")
    bottom.axhline(lim.limit_C, ls="--", color="black", lw=0.9, label=f"limit {lim.limit_C:g} degC")
    bottom.axhline(lim.limit_C - lim.margin_K, ls=":", color="black", lw=0.9, label=f"limit less the margin "
                   f"({lim.margin_K:g} K)")
    bottom.set_xlabel("test time (min)")
    bottom.set_ylabel("winding temperature (degC)")
    bottom.legend(loc="lower right", fontsize=7, frameon=False)
    bottom.grid(alpha=0.3)
    promised = "; ".join(f"{n} ± {plan.stderr_after[n]:.3g} {plan.units.get(n, '')}".rstrip() + " expected"
                         for n in plan.identify)
    fig.suptitle(f"{plan.actuator}: a test to size {', '.join(plan.identify)} ({promised})", fontsize=10)
    return save(fig, Path(folder) / f"plan_{file_stem(plan.actuator)}.png")
