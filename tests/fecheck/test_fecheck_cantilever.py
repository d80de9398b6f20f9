"""The CalculiX pipeline's elastic side and its rigid-body moment against beam theory: a beam bent
by a moment on a rigid end (what fe-check's pinion is: a body turned by the torque on a rigid rim
whose centre is held, its loaded rotation read from the rotation node, its stress from the .frd).

The box of tests/fe/test_fe_solver.py (``beveloid.fe.box``), clamped at x = 0, its end face x = L a
``*RIGID BODY`` under a moment M0 about z through the face's centre, whose x and y are held (as the
pinion's): a clamped-pinned beam under an end moment.  Its end rotation, with shear (Timoshenko;
Przemieniecki's beam stiffness k = (4 + Phi) E I / ((1 + Phi) L), Phi = 12 E I / (k_s G A L^2)), is
M0 (1 + Phi) L / ((4 + Phi) E I); its bending moment runs linearly from M0 at the end to -M0 / 2
at the clamp (carry-over 1/2), sigma_xx = -M(x) (y - B/2) / I."""
from __future__ import annotations

import numpy as np
import pytest

from beveloid.fe.box import box_mesh
from beveloid.fecheck import Body, ContactDeck, RigidLoad, ccx_path, run_ccx, write_deck
from beveloid.fecheck.pair_model import ccx_order
from beveloid.fecheck.results import read_dat, read_frd

E, NU = 2.0e5, 0.3
L, B, H = 100.0, 10.0, 10.0
M = 1.0e5  #: N mm: 60 MPa of bending stress at the loaded end


@pytest.mark.skipif(ccx_path() is None, reason="needs CalculiX (ccx, Debian package calculix-ccx)")
def test_cantilever_under_an_end_moment_matches_beam_theory(tmp_path):
    mesh = box_mesh((L, B, H), 3.4)
    body = Body("BEAM", mesh.nodes, ccx_order(mesh.nodes, mesh.tets), {}, dict(mesh.node_sets))
    deck = ContactDeck(bodies=(body,), young_mpa=E, poisson=NU, contact_pairs=(), fixed=("BEAM.x0",),
                       rigid=RigidLoad("BEAM", "x1", centre_mm=(L, B / 2, H / 2), moment_nmm=M))
    info = write_deck(deck, tmp_path / "beam.inp")
    run = run_ccx(tmp_path / "beam.inp")
    inertia = H * B ** 3 / 12
    k_s = 10 * (1 + NU) / (12 + 11 * NU)  # Cowper's shear coefficient of a rectangle
    phi = 12 * E * inertia / (k_s * E / (2 * (1 + NU)) * B * H * L ** 2)
    # the end rotation; the rigid end (no anticlastic bending there) and the clamp (no Poisson contraction)
    # stiffen the beam locally, over about one depth at each end
    rotation = read_dat(run.file("dat")).displacements[info["rot_node"]][2]
    assert rotation == pytest.approx(M * (1 + phi) * L / ((4 + phi) * E * inertia), rel=0.02)
    # the bending stress on the outer fibres y = 0 and y = B, from x = L / 2 to 0.8 L (clear of both ends)
    stress = read_frd(run.file("frd"))["STRESS"].on(info["nodes"])[: len(mesh.nodes), 0]
    x, y = mesh.nodes[:, 0], mesh.nodes[:, 1]
    span = (x > 0.5 * L) & (x < 0.8 * L)
    for fibre in (0.0, B):
        on = span & (np.abs(y - fibre) < 1e-9)
        beam = -M * (1.5 * x[on] / L - 0.5) * (fibre - B / 2) / inertia
        assert on.sum() > 10 and np.max(np.abs(stress[on] - beam)) < 0.02 * np.max(np.abs(beam))
