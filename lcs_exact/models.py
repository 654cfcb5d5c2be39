"""Builders for linear complementarity systems, in one place (DESIGN.md section 6).

* :func:`mechanical` (:mod:`lcs_exact.mechanics`): M q'' + D q' + K q = E^T u, y = E q (8.1)-(8.3);
* :func:`circuit`, :func:`circuit_ports` (:mod:`lcs_exact.circuits`): RLC networks with ideal diodes;
* :func:`relay` (:mod:`lcs_exact.relays`): x' = A x + B w, w in Sgn(C x), with a constant state
  for the relay levels and ``lcs.embed(x)`` = (x, 1);
* the examples of :mod:`lcs_exact.examples` (``two_carts``, ``two_carts_with_hook``, ...), kept
  here under their old names.
"""
from __future__ import annotations

from .circuits import circuit, circuit_ports
from .examples import diode_bridge, filippov_spiral, half_wave_rectifier, two_carts, two_carts_with_hook
from .mechanics import mechanical
from .relays import relay

__all__ = ["mechanical", "circuit", "circuit_ports", "relay", "two_carts", "two_carts_with_hook",
           "half_wave_rectifier", "diode_bridge", "filippov_spiral"]
