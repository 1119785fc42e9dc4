"""A test component shared by the initialization and linearization tests."""
from pdbfs import Parameter, eq
from pdbfs.modelling import Component, Flange, Variable


class Hardening(Component):
    """A spring f = k (s + b s^3) on its stretch s: two in series make the
    node between them an algebraic variable (IDAS)."""
    k = Parameter(1.0, "N/m", "Stiffness", positive=True)
    b = Parameter(0.0, "1/m2", "Cubic hardening")

    def declare(self):
        self.flange_a, self.flange_b = Flange(), Flange()
        self.s = Variable("m", "Stretch")
        self.f = Variable("N", "Force")

    def equations(self):
        return [eq(self.s, self.flange_b.s - self.flange_a.s),
                eq(self.flange_b.f, self.f), eq(self.flange_a.f, -self.f),
                eq(self.f, self.k * (self.s + self.b * self.s ** 3))]
