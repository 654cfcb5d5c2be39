"""Builders for linear complementarity systems, in one place (docs/paper-to-api.md).

* :func:`mechanical` (:mod:`lcs_exact.mechanics`): M q'' + D q' + K q = f + E^T u, y = E q + g
  (8.1)-(8.3), with forces and gaps as sources (a source in a gap is a moving obstacle), Newton's
  impact law (``restitution``) and compliant contacts (``compliance``: y = E q + g + C_c u);
* :func:`driven` (:mod:`lcs_exact.exosystems`): x' = A x + B u + E w(t), y = C x + D u + F w(t) with
  sources w (:mod:`lcs_exact.sources`) carried by appended exosystem states;
* :func:`circuit`, :func:`circuit_ports` (:mod:`lcs_exact.circuits`): RLC networks with ideal diodes;
* :func:`relay` (:mod:`lcs_exact.relays`): x' = A x + B w, w in Sgn(C x), with a constant state
  for the relay levels and ``lcs.embed(x)`` = (x, 1); with sources x' = A x + B w + E s(t),
  w in Sgn(C x + F s(t)) (``w=`` the sources, as for :func:`driven`: a belt's speed inside Coulomb
  friction's sign);
* :func:`scheduled`, :func:`sampled` (:mod:`lcs_exact.schedule`): data that switch at scheduled
  times (a PWM switch), sampled-data control with a held input;
* the examples of :mod:`lcs_exact.examples` (``two_carts``, ``two_carts_with_hook``, ...), kept
  here under their old names.
"""
from __future__ import annotations

from .builders import circuit, circuit_ports
from .builders import driven
from .builders import (ball_column, ball_on_spring, bouncing_ball, diode_bridge, diode_bridge_cap_filter,
                       filippov_spiral, half_wave_rectifier, newtons_cradle, sine_rectifier, two_carts, buck_converter,
                       two_carts_with_hook)
from .builders import mechanical
from .builders import relay
from .builders import sampled, scheduled

__all__ = ["mechanical", "driven", "circuit", "circuit_ports", "relay", "scheduled", "sampled", "two_carts", "two_carts_with_hook",
           "half_wave_rectifier", "diode_bridge", "filippov_spiral", "bouncing_ball", "ball_on_spring",
           "ball_column", "newtons_cradle", "sine_rectifier", "diode_bridge_cap_filter", "buck_converter"]
