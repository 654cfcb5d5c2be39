"""Builders of an LCS from a description: exosystems (``exosystems``), mechanical systems
(``mechanics``), circuits (``circuits``), relays (``relays``), the examples (``examples``), and
scheduled and sampled systems (``scheduled``, ``sampled``, whose home is ``dynamics``).

This is the subpackage's door: other subpackages and users import what ``__all__`` names,
from here; the modules behind it are its own.
"""
from __future__ import annotations

from .exosystems import driven
from .mechanics import mechanical
from .circuits import circuit, circuit_ports
from .relays import relay
from .examples import (ball_column, ball_on_spring, bouncing_ball, buck_converter, cart_chain, diode_bridge,
                       diode_bridge_cap_filter, filippov_spiral, half_wave_rectifier, newtons_cradle,
                       sine_rectifier, two_carts, two_carts_with_hook)
from ..dynamics import sampled, scheduled

__all__ = ["driven", "mechanical", "circuit", "circuit_ports", "relay", "ball_column", "ball_on_spring",
           "bouncing_ball", "buck_converter", "cart_chain", "diode_bridge", "diode_bridge_cap_filter",
           "filippov_spiral", "half_wave_rectifier", "newtons_cradle", "sine_rectifier", "two_carts",
           "two_carts_with_hook", "sampled", "scheduled"]
