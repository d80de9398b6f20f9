"""The tooth body: the member cut by the unmodified rack, on which the FE tooth is built.

A flank modification (crowning, tip and end relief, lead slope, a user model's twist) moves the flank
by micrometres: it changes where and how hard the teeth touch, which the loaded contact takes from
the modified flank itself (its gaps and contact points), but not how the tooth bends or where its
root stress peaks.  So the FE tooth (:mod:`beveloid.fe.tooth`) is meshed, solved and cached for the
member's **body**: the same member with the ``involute`` surface (the rack's straight flank,
uncrowned) and the root fillet of that rack, which meet at the form limit by construction.  The
loads are applied at the modified flank's contact points (:class:`beveloid.fe.contact.FeTooth` maps
points onto the body's load grid by their axial position and radius).  One FE solve serves every
modification, error set and torque of a macro geometry; the FE cache key holds the body only.

How far a modified flank departs from its body is measured in :mod:`beveloid.tooth.departure`.
"""
from __future__ import annotations

import dataclasses

__all__ = ["BODY_SURFACE", "body_pair", "is_body"]

#: the surface model of every member's FE body
BODY_SURFACE = "involute"


def is_body(geometry, member: str) -> bool:
    """True when the member already is its own body (the involute flank, no options)."""
    m = geometry.member(member)
    return m.tooth_surface == BODY_SURFACE and not m.surface_options


def body_pair(pair, member: str):
    """``pair`` (a Pair or a PairGeometry) with ``member`` cut by the unmodified rack (see the module
    docstring); the same object when the member is already its body."""
    geometry = getattr(pair, "geometry", pair)
    if is_body(geometry, member):
        return pair
    body = dataclasses.replace(geometry.member(member), tooth_surface=BODY_SURFACE, surface_options=())
    geometry = dataclasses.replace(geometry, **{member: body})
    return dataclasses.replace(pair, geometry=geometry) if hasattr(pair, "geometry") else geometry
