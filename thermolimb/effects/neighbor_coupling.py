"""Heat conducted between neighbouring actuators (consecutive in a limb, and in the log's order)."""

from __future__ import annotations

from dataclasses import dataclass

from ..model.terms import Parameter, Term, register_term
from .base import Effect, Hidden, PlantEffect, register


@register_term
class NeighborCouplingTerm(Term):
    """Heat conducted from neighbouring actuators: ``k (mean T_neighbours - T)``.

    Neighbours are the actuators next to this one in the log's order (a limb
    logged joint by joint), as :meth:`thermolimb.logs.ThermalLog.series` gives them.
    """

    name = "neighbor_coupling"
    label = "heat from neighbours"
    description = "conduction from the other actuators, from their measured temperatures"
    parameters = (
        Parameter("neighbor_ratio", "1", 0.0, 10.0, 0.1,
                  "neighbour conductance over the conductance to ambient",
                  "neighbours whose temperature differs from this actuator's", plausible=(0.0, 5.0)),
    )
    columns = ("neighbors",)

    def forms(self, s):
        return (s.neighbor_mean_C,)

    def combine(self, p, forms):
        k = p["neighbor_ratio"]
        return k * forms[0], -k

    def features(self, s, temperature_C):
        return (s.neighbor_mean_C - temperature_C)[:, None]


@dataclass(frozen=True)
class NeighborCoupling(PlantEffect):
    """Conduction between the outer nodes of neighbouring actuators (consecutive in the plant's order)."""

    name = "neighbor_coupling"
    conductance_W_per_K: float = 0.3

    def wire(self, net):
        g = self.conductance_W_per_K
        for a, b in zip(net.outer[:-1], net.outer[1:]):
            for p, q in ((a, b), (b, a)):
                net.A[p, p] -= g * net.inv_capacity[p]
                net.A[p, q] += g * net.inv_capacity[p]


# the residual's correlation with a neighbour's temperature ("temperature of J1") speaks for it
register(Effect("neighbor_coupling", NeighborCouplingTerm, NeighborCoupling, residual="temperature of",
                hidden=Hidden("neighbor_coupling", "neighbor_coupling"), rides="neighbors"))
