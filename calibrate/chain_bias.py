"""The contact chain's mean bias against the full FEA, as a function of the parameters: a
low-rank model fitted to a space-filling design of FE runs (validation/chain_bias_design.py).

At the true parameters the chain's force differs from the full FEA's by a smooth,
deterministic bias (the impulse a few per cent low, the rise early, the peak low) that the
calibration would otherwise absorb into alpha, E and the effects. It moves with the
contact: it is modelled in the chain's own contact phase

    tau = (t - t_s) / (t_e - t_s),   t_s, t_e: where the chain's force first and last
                                     exceeds ``CONTACT_LEVEL`` of its peak,

as  d(t) = P B(tau; x),  P the chain's peak force and

    B(tau; x) = m(tau) + sum_k c_k(x) u_k(tau),   c_k(x) = w_k . [1, z(x)]

m the mean over the design runs of each run's bias shape (its zero-phase low-passed
discrepancy LP[F_FEA - F_chain] at ``CORRECTION_BAND_HZ``, over P), u_k its first
``COMPONENTS`` principal shapes, and the coefficients linear (ridge, ``RIDGE``) in the
standardised features z(x): ln alpha, E factor, friction mu, drum speed, initial angle
offset, object offset and the damping kind (-1 global, +1 relative). Outside the phase
grid the bias is 0. ``residual_std`` is the RMS of the shapes' misfit over the design
(over P): the part of the bias the model leaves.

:data:`BUNDLED_BIAS` holds the model fitted to the bundled design (data/contact/).
"""
import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ccedi.errors import InputError

from .contact_model import CORRECTION_BAND_HZ, zero_phase_lowpass

BUNDLED_BIAS = Path(__file__).parents[1] / "data" / "contact" / "chain_bias.json"
CONTACT_LEVEL = 0.05
"""Fraction of the chain's peak force that marks its contact start and end [-]."""
PHASE = np.linspace(-0.2, 1.3, 301)
"""The phase grid of the bias shapes [-]."""
COMPONENTS = 3
"""Principal shapes kept."""
RIDGE = 1.0
"""Ridge penalty on the coefficients' feature weights (standardised features) [-]."""
FEATURES = ("ln_alpha", "E_factor", "friction_mu", "omega_rad_s", "theta0_offset_rad", "object_radial_offset_m",
            "relative_damping")


def contact_window(time_s, force):
    """(t_s, t_e, P) of a force: where it first and last exceeds ``CONTACT_LEVEL`` of its
    peak P [s, s, N].

    Parameters
    ----------
    time_s : numpy.ndarray
        Times [s].
    force : numpy.ndarray
        Force [N].

    Returns
    -------
    tuple of float
        Contact start and end [s] and the peak [N].

    Raises
    ------
    InputError
        No contact: the force never rises above 0.
    """
    peak = float(np.max(force))
    if not peak > 0.0:
        raise InputError("chain bias: the chain's force never rises above 0 N; no contact to align the bias with")
    above = np.flatnonzero(force > CONTACT_LEVEL * peak)
    return float(time_s[above[0]]), float(time_s[above[-1]]), peak


def run_bias(time_s, fe_force, chain_force):
    """The smooth bias of one run: LP[F_FEA - F_chain] (``CORRECTION_BAND_HZ``) [N].

    Parameters
    ----------
    time_s : numpy.ndarray
        Uniform times [s].
    fe_force, chain_force : numpy.ndarray
        The FE's and the chain's force at them [N].

    Returns
    -------
    numpy.ndarray
        The low-passed discrepancy [N].
    """
    return zero_phase_lowpass(time_s, fe_force - chain_force, CORRECTION_BAND_HZ)


def features(v, damping):
    """The feature vector x of parameter values (absent effects at the declared values:
    mu 0.6, drum speed 2.095 rad/s, no offsets).

    Parameters
    ----------
    v : dict
        ``alpha_per_s``, ``E_factor`` and any physical effect's values.
    damping : str
        "global" or "relative".

    Returns
    -------
    numpy.ndarray
        The features in the order of :data:`FEATURES`.
    """
    return np.array([np.log(v["alpha_per_s"]), v["E_factor"], v.get("friction_mu", 0.6), v.get("omega_rad_s", 2.095),
                     v.get("theta0_offset_rad", 0.0), v.get("object_radial_offset_m", 0.0),
                     1.0 if damping == "relative" else -1.0])


@dataclass(frozen=True)
class ChainBias:
    """The fitted bias model (module docstring).

    Parameters
    ----------
    mean : numpy.ndarray
        m on :data:`PHASE` [-].
    shapes : numpy.ndarray
        (k, len(PHASE)): u_k.
    weights : numpy.ndarray
        (k, 1 + len(FEATURES)): w_k.
    center, scale : numpy.ndarray
        The features' standardisation.
    residual_std : float
        RMS misfit of the design's shapes [-].
    runs : int
        Design runs fitted.
    """

    mean: np.ndarray
    shapes: np.ndarray
    weights: np.ndarray
    center: np.ndarray
    scale: np.ndarray
    residual_std: float
    runs: int

    def shape(self, v, damping):
        """B(tau; x) on :data:`PHASE` [-].

        Parameters
        ----------
        v : dict
            Parameter values.
        damping : str
            The damping kind.

        Returns
        -------
        numpy.ndarray
            The bias shape.
        """
        z = np.concatenate([[1.0], (features(v, damping) - self.center) / self.scale])
        return self.mean + (self.weights @ z) @ self.shapes

    def force_bias(self, time_s, chain_force, *, v, damping):
        """d(t) [N] for the chain's force at parameter values ``v``.

        Parameters
        ----------
        time_s : numpy.ndarray
            Times [s].
        chain_force : numpy.ndarray
            The chain's force at them [N] (sets the contact phase and the peak).
        v : dict
            Parameter values.
        damping : str
            The damping kind.

        Returns
        -------
        numpy.ndarray
            The bias to add to the chain's force [N]; 0 where the chain makes no contact.
        """
        if not np.max(chain_force) > 0.0:
            return np.zeros_like(chain_force)
        t_s, t_e, peak = contact_window(time_s, chain_force)
        tau = (time_s - t_s) / max(t_e - t_s, 1e-9)
        return peak * np.interp(tau, PHASE, self.shape(v, damping), left=0.0, right=0.0)

    def summary(self):
        """JSON-ready description.

        Returns
        -------
        dict
            Components, runs, residual std and the shapes' RMS.
        """
        return {"components": len(self.shapes), "runs": self.runs, "residual_std_of_peak": self.residual_std,
                "mean_shape_rms_of_peak": float(np.sqrt(np.mean(self.mean**2))), "features": list(FEATURES)}

    def write(self, path):
        """Write the model as JSON.

        Parameters
        ----------
        path : str or pathlib.Path
            The file.
        """
        data = {"what": "the contact chain's mean bias against the full FEA (ccedi.calibrate.chain_bias); "
                        "shapes over the chain's contact phase, in units of its peak force [-]",
                "phase": PHASE.tolist(), "mean": self.mean.tolist(), "shapes": self.shapes.tolist(),
                "weights": self.weights.tolist(), "feature_center": self.center.tolist(),
                "feature_scale": self.scale.tolist(), "residual_std_of_peak": self.residual_std, "runs": self.runs,
                "features": list(FEATURES)}
        Path(path).write_text(json.dumps(data, indent=1) + "\n")

    @classmethod
    def read(cls, path=BUNDLED_BIAS):
        """The model written by :meth:`write`.

        Parameters
        ----------
        path : str or pathlib.Path, optional
            The file. Default :data:`BUNDLED_BIAS`.

        Returns
        -------
        ChainBias
            The model.

        Raises
        ------
        InputError
            A file that is missing or not such a model.
        """
        try:
            d = json.loads(Path(path).read_text())
            phase = np.asarray(d["phase"], dtype=float)
            model = cls(mean=np.array(d["mean"]), shapes=np.array(d["shapes"]), weights=np.array(d["weights"]),
                        center=np.array(d["feature_center"]), scale=np.array(d["feature_scale"]),
                        residual_std=float(d["residual_std_of_peak"]), runs=int(d["runs"]))
        except (OSError, ValueError, KeyError, TypeError) as err:
            raise InputError(f"chain bias model {path}: cannot be read ({err}); "
                             f"regenerate it with validation/chain_bias_design.py") from None
        if phase.shape != PHASE.shape or not np.allclose(phase, PHASE):
            raise InputError(f"chain bias model {path}: its phase grid is not this version's; "
                             f"regenerate it with validation/chain_bias_design.py")
        return model


def fit_chain_bias(runs, components=COMPONENTS, ridge=RIDGE):
    """The bias model of a design's runs (module docstring).

    Parameters
    ----------
    runs : list of tuple
        (damping kind, parameter values, time_s, FE force, chain force) per run [-, -, s, N, N].
    components : int, optional
        Principal shapes kept. Default :data:`COMPONENTS`.
    ridge : float, optional
        Ridge penalty. Default :data:`RIDGE`.

    Returns
    -------
    ChainBias
        The fitted model.

    Raises
    ------
    InputError
        Fewer runs than components + 2.
    """
    if len(runs) < components + 2:
        raise InputError(f"chain bias: {len(runs)} design runs; at least {components + 2} needed")
    shapes, X = [], []
    for kind, v, t, fe, chain in runs:
        t_s, t_e, peak = contact_window(t, chain)
        tau = (t - t_s) / (t_e - t_s)
        shapes.append(np.interp(PHASE, tau, run_bias(t, fe, chain)) / peak)
        X.append(features(v, kind))
    S, X = np.array(shapes), np.array(X)
    center, scale = X.mean(axis=0), X.std(axis=0)
    scale = np.where(scale > 0.0, scale, 1.0)
    Z = np.hstack([np.ones((len(X), 1)), (X - center) / scale])
    mean = S.mean(axis=0)
    _, _, vt = np.linalg.svd(S - mean, full_matrices=False)
    u = vt[:components]
    C = (S - mean) @ u.T                                        # (runs, k) coefficients
    penalty = ridge * np.diag([0.0] + [1.0] * (Z.shape[1] - 1))
    W = np.linalg.solve(Z.T @ Z + penalty, Z.T @ C).T           # (k, 1 + features)
    misfit = S - (mean + (Z @ W.T) @ u)
    return ChainBias(mean=mean, shapes=u, weights=W, center=center, scale=scale,
                     residual_std=float(np.sqrt(np.mean(misfit**2))), runs=len(runs))
