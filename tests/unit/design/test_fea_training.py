"""The surrogate corrected by a reference model run at a few training designs
(:func:`ccedi.design.recheck.fea_correction`): with a stand-in reference (the ROM of a
finger 20 % stiffer, cheap where the full FEA takes minutes), the corrected ROM meets the
reference at the training designs exactly and off them much closer than the ROM alone;
training levels outside their range are refused in one line."""
from dataclasses import replace

import numpy as np
import pytest

from ccedi.design.recheck import fea_correction
from ccedi.design.surrogate import design_space, rom_factory, run_rom
from ccedi.errors import InputError
from ccedi.fea.contact.drum import DrumSetup

SPACE = design_space((100.0, 400.0), (4.0, 5.0))


def stiffer(setup):
    """The stand-in reference: the ROM of the finger with E x 1.2."""
    return rom_factory(replace(setup, finger_material=replace(setup.finger_material, E=1.2 * setup.finger_material.E)))


def test_the_corrected_rom_meets_the_reference_at_and_between_the_training_designs(tmp_path):
    setup = DrumSetup()
    correction, reference, cached = fea_correction(setup, SPACE, levels=(2, 2), directory=tmp_path,
                                                   model_factory=stiffer)
    assert not cached and len(reference) == 4 and (tmp_path / "fea_training.csv").exists()
    rom = run_rom(setup, reference[["alpha_per_s", "length_m"]].to_numpy(), variables=SPACE)
    corrected = correction.apply(rom)
    force = "sensor_peak_force_N"
    np.testing.assert_allclose(corrected[force], reference[force], rtol=1e-9)
    between = [(200.0, 0.1143), (150.0, 0.1206)]                     # 4.5 and 4.75 in
    rom_between = run_rom(setup, between, variables=SPACE)
    truth = run_rom(setup, between, variables=SPACE, model_factory=stiffer)
    plain = np.abs(rom_between[force] / truth[force] - 1.0)
    fixed = np.abs(correction.apply(rom_between)[force] / truth[force] - 1.0)
    assert plain.min() > 0.03 and fixed.max() < 0.3 * plain.min(), (plain, fixed)
    _, _, cached = fea_correction(setup, SPACE, levels=(2, 2), directory=tmp_path, model_factory=stiffer)
    assert cached


@pytest.mark.parametrize("levels", [(1, 3), (3, 6), (3,), (2.5, 3)])
def test_training_levels_outside_their_range_are_refused(levels):
    with pytest.raises(InputError, match="FEA correction training levels"):
        fea_correction(DrumSetup(), SPACE, levels=levels, model_factory=stiffer)
