"""The loss factor -> alpha conversion against CCEDI's own damping model: the full explicit
FE of the clamped 4.5-in finger with a given mass-proportional alpha is struck at the tip,
its first-mode damping ratio and frequency are read from the free decay of the tip (a
damped sinusoid fitted to the record, no finger model), tan delta = 2 zeta is converted
back at that frequency, and the given alpha must come back within 5 %."""
import math

import pytest

from ccedi.calibrate.adequacy import free_decay_mode
from ccedi.design.compounds import alpha_from_loss_factor, loss_factor_from_alpha
from ccedi.fea.cases.studies import finger_impulse_model
from ccedi.rom.finger_identification import finger_omega1

ALPHAS = (10.0, 40.0)
"""Given alphas [1/s]: zeta_1 = 0.056 and 0.22 on the 4.5-in finger (alpha_cr about 174), the
range published loss factors of solid rubbers (0.1-0.45) give."""
PULSE_S = 0.01
"""Tip pulse: 0.3 N held for 10 ms (rings the first mode, barely the second)."""
RUN_S = 0.3
"""Record length: 4 periods of the first mode (14.2 Hz)."""


@pytest.fixture(scope="module")
def records():
    """{alpha: (time_s, tip_displacement_m)} of the full FE finger (about 7 s per run)."""
    model = finger_impulse_model(4.5, force_N=0.3, duration_s=PULSE_S)
    return {alpha: model.run(alpha, RUN_S, 600).tip_signal() for alpha in ALPHAS}


@pytest.mark.parametrize("alpha", ALPHAS)
def test_loss_factor_of_the_fe_finger_converts_back_to_its_alpha(records, alpha):
    t, y = records[alpha]
    mode = free_decay_mode(t, y, free_from_s=PULSE_S, noise_std_m=1e-9)
    assert mode.measurable
    omega_1 = 2.0 * math.pi * mode.frequency_hz
    tan_delta = 2.0 * mode.damping_ratio
    assert alpha_from_loss_factor(tan_delta, omega_1) == pytest.approx(alpha, rel=0.05)
    # and the finger's tan delta is what the conversion predicts from the given alpha at
    # the FE finger's first mode, with no record
    assert tan_delta == pytest.approx(loss_factor_from_alpha(alpha, finger_omega1(4.5)), rel=0.05)
