"""What a Result reads its run through: the ``RunSource`` protocol. The
Simulator that made the run (pdbfs.simulation.run) is one, a run with inputs'
Driven another; a Result names neither, so this folder imports nothing of
the runs that make its Results."""
from __future__ import annotations

from typing import TYPE_CHECKING, Any, Protocol

if TYPE_CHECKING:
    import numpy as np

    from pdbfs.modelling import DAE

    from ..state import RigState


class RunSource(Protocol):
    """The rig and the evaluations and integrations a Result asks of the run
    that made it (values off the grid, the summary's own solution, a contact
    force's impulse). Arrays: ``grid`` (n,) in s, states ``X`` (nx, n),
    algebraics ``Z`` (nz, n), parameters ``p`` (np,); settings as a Result's.

    A run with inputs has three more, read where present: ``p_at(p, t)``
    (the parameters with the inputs' values at t), ``by_segments`` (its
    integration piece by piece between the inputs' breakpoints) and
    ``known_until`` (s: the end of the inputs' traces)."""

    dae: DAE
    state: RigState

    def outputs(self, grid: np.ndarray, X: np.ndarray, Z: np.ndarray, p: np.ndarray,
                rows: list[int] | None = None) -> np.ndarray:
        """The outputs ``rows`` (all if None) on ``grid``."""

    def rates_on(self, grid: np.ndarray, X: np.ndarray, Z: np.ndarray, p: np.ndarray,
                 name: str) -> np.ndarray:
        """The time derivative of the output ``name`` on ``grid``."""

    def events_on(self, grid: np.ndarray, X: np.ndarray, Z: np.ndarray,
                  p: np.ndarray) -> np.ndarray:
        """The event indicators on ``grid``."""

    def rows_rates_events(self, grid: np.ndarray, X: np.ndarray, Z: np.ndarray, p: np.ndarray,
                          names: list[str]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The outputs ``names``, their rates and the event indicators on ``grid``."""

    def step(self, x: np.ndarray, p: np.ndarray, t0: float, h: float, rtol: float, atol: float,
             method: str, max_step: float | None = None, backend: str = "casadi",
             max_num_steps: int = ...) -> tuple[np.ndarray, np.ndarray]:
        """(states, algebraics) at t0 + h from the states ``x`` at t0."""

    def compiled(self, method: str | None = None) -> Any:
        """The rig's compiled library."""

    def integrate_c(self, grid: np.ndarray, x0: np.ndarray, p: np.ndarray, rtol: float,
                    atol: float, method: str, max_step: float | None,
                    max_num_steps: int) -> np.ndarray:
        """The states on ``grid`` from ``x0`` by the compiled driver."""

    def integrate_shifted(self, grid: np.ndarray, x0: np.ndarray, p: np.ndarray, rtol: float,
                          atol: float, method: str, max_step: float | None,
                          max_num_steps: int = ...) -> tuple[np.ndarray, np.ndarray]:
        """(states, algebraics) on ``grid`` from ``x0`` at grid[0] through CasADi."""

    def located(self, grid: np.ndarray, x0: np.ndarray, p: np.ndarray, rtol: float, atol: float,
                method: str, max_step: float | None, max_num_steps: int,
                force: str | None = None) -> tuple:
        """(states, algebraics, the impulse of ``force`` or None) on ``grid``,
        state events located."""
