"""Gauss-Legendre steps of an affine field on a fixed time grid, kept for any reader.

:class:`GridFlow` integrates r' = A(t) r + c(t) with steps of ``h`` on the grid
t0 + k h, computing the steps in blocks as far as asked and keeping the states; the
state at any time t is one shorter step from the grid point before it.  A headless run
reading its sample times and a live view reading its frame times therefore get the
same state at the same time, whatever the frame length.
"""

from __future__ import annotations

import numpy as np
from analyzer_lab.lessons.kit.integrators import LinearCoeffs, apply_propagators, gl_propagators


class GridFlow:
    """The states of ``r' = A(t) r + c(t)`` from ``r0 (N, d)`` at ``t0`` (``t >= t0``)."""

    BLOCK = 128

    def __init__(
        self,
        coeffs: LinearCoeffs,
        r0: np.ndarray,
        t0: float = 0.0,
        h: float = 0.01,
        stages: int = 3,
    ) -> None:
        self.coeffs, self.t0, self.h, self.stages = coeffs, float(t0), float(h), stages
        self.states = np.asarray(r0, dtype=float)[None].copy()
        self._comp: np.ndarray | None = None  # compensated-summation carry

    def _extend(self, upto: int) -> None:
        blocks = [self.states]
        last, k = self.states[-1], len(self.states) - 1
        while k < upto:
            D, phi = gl_propagators(
                self.coeffs, self.t0 + k * self.h, self.h, self.BLOCK, self.stages
            )
            seq, self._comp = apply_propagators(D, phi, last, self._comp)
            seq = seq[1:]
            blocks.append(seq)
            last, k = seq[-1], k + self.BLOCK
        self.states = np.concatenate(blocks)

    def at(self, t: np.ndarray) -> np.ndarray:
        """States ``(m, N, d)`` at the times ``t (m,)``."""
        s = np.asarray(t, dtype=float) - self.t0
        j = np.maximum(np.floor(s / self.h + 1e-9).astype(int), 0)
        if int(j.max()) >= len(self.states):
            self._extend(int(j.max()))
        out = self.states[j].copy()
        rest = s - j * self.h
        for i in np.nonzero(rest > 1e-12 * self.h)[0]:
            D, phi = gl_propagators(self.coeffs, self.t0 + j[i] * self.h, rest[i], 1, self.stages)
            out[i] = out[i] + (D[0] @ out[i][:, :, None])[:, :, 0] + phi[0]
        return out
