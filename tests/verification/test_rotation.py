"""Rotating finger without contact: global mass damping drags the finger back by the
Euler-Bernoulli deflection under the drag load alpha rho A omega r; relative damping
(in the drum frame) does not."""
import numpy as np
import pytest

from ccedi.fea.cases.beam_theory import drum_drag_tip_deflection, ellipse_section_properties
from ccedi.fea.contact.drum import DrumSetup, finger_on_drum
from ccedi.fea.material import RUBBER
from ccedi.fea.solvers.explicit import run

pytestmark = pytest.mark.slow          # each test runs the rotating finger for about a minute

SETUP = DrumSetup(finger_length_m=0.1143, object_center_m=(5.0, 5.0), theta0_rad=0.0)
ALPHA = 20.0


def trailing_tip_deflection(damping):
    model, v0 = finger_on_drum(SETUP, ALPHA, damping=damping)
    res = run(model, 0.6, n_outputs=20, v0=v0)
    t = res.summary["t_final_s"]
    c, s = np.cos(-SETUP.omega_rad_s * t), np.sin(-SETUP.omega_rad_s * t)
    back = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])    # undo the drum rotation
    tip = model.mesh.node_sets["tip"]
    u = (res.x[tip] @ back.T - model.mesh.nodes[tip]).mean(axis=0)
    return -u[1]                    # theta0 = 0: e_theta is +y; lagging behind is -y


def drag_deflection():
    area, inertia = ellipse_section_properties()
    return drum_drag_tip_deflection(ALPHA, RUBBER.rho, area, omega=SETUP.omega_rad_s, drum_radius_m=SETUP.drum_radius_m,
                                    length_m=SETUP.finger_length_m, E=RUBBER.E, second_moment=inertia)


def test_global_damping_drags_the_finger_back():
    assert trailing_tip_deflection("global") == pytest.approx(drag_deflection(), rel=0.06)


def test_relative_damping_leaves_the_finger_straight():
    assert abs(trailing_tip_deflection("relative")) < 0.03 * drag_deflection()
