"""A free decay fitted by the slow flow (45) with the forcing off: exact recovery from a decay
integrated by scipy's Radau (not the fit's DOP853), the envelope of a signal against its closed
form, the command, and the refusals."""

import warnings

import numpy as np
import pytest
from scipy import integrate

from slosh_bif import get_preset
from slosh_bif.cli import main
from slosh_bif.identify.time_series import TimeRecord, envelope, fit_time_series, read_time_record
from slosh_bif.slowflow.flow import AsymptoticsWarning, SlowFlow

TRUTH = get_preset("fig10").params  # lam = 0.35, gamma = 0.2, eps = 0.05


def _radau(params, A0, psi0, tau):
    """A(tau) of (45) at ``params`` from (A0, psi0), by scipy's Radau; and A_min."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AsymptoticsWarning)
        flow = SlowFlow(params)
        run = integrate.solve_ivp(
            lambda t, z: flow.rhs(z[0], z[1]),
            (0.0, params.eps * tau[-1]),
            [A0, psi0],
            method="Radau",
            rtol=1e-12,
            atol=1e-13,
            t_eval=params.eps * tau,
        )
    return run.y[0], flow.A_min


@pytest.fixture(scope="module")
def decay():
    """A(tau) on S+ from A = 3 by Radau on (45) with Abar = 0, above 1.05 A_min."""
    tau = np.linspace(0.0, 200.0, 25)
    A, A_min = _radau(TRUTH.replace(Abar=0.0), 3.0, 0.0, tau)
    keep = A > 1.05 * A_min
    return TimeRecord(tau[keep], A[keep], None, "radau")


def test_a_decay_of_the_slow_flow_gives_back_the_damping(decay):
    fit = fit_time_series(decay, TRUTH.replace(lam=0.5, gamma=0.15), ["lam", "gamma"])
    assert fit.converged and fit.rms < 1e-8
    assert fit.values["lam"] == pytest.approx(TRUTH.lam, rel=1e-6)
    assert fit.values["gamma"] == pytest.approx(TRUTH.gamma, rel=1e-6)
    assert fit.values["A0"] == pytest.approx(3.0, rel=1e-8)
    # the decay separates the impacts' loss (it falls with A) from the vessel's (it does not)
    assert abs(fit.correlation[0, 1]) < 0.99


def test_the_envelope_of_a_slowly_decaying_sine():
    """|2 e^(-k t) sin(t + 0.3)| peaks every pi at the height 2 e^(-k t) / sqrt(1 + k^2) (there
    tan(t + 0.3) = 1/k): the parabola through three samples 0.02 apart finds it to 1e-7."""
    tau = np.arange(0.0, 100.0, 0.02)
    t, A = envelope(tau, 2.0 * np.exp(-0.01 * tau) * np.sin(tau + 0.3))
    assert len(t) == 32 and np.abs(A - 2.0 * np.exp(-0.01 * t) / np.sqrt(1 + 1e-4)).max() < 1e-7


def test_slosh_bif_fit_a_decay_and_its_refusals(tmp_path, decay, capsys):
    data = tmp_path / "decay.csv"
    data.write_text("tau,A\n" + "".join(f"{t:.17g},{a:.17g}\n" for t, a in zip(decay.tau, decay.A)))
    out = tmp_path / "fit"
    args = ["fit", "--preset", "fig10", "--set", "gamma=0.15", "--data", str(data), "--free", "gamma"]
    assert main(args + ["--out", str(out)]) == 0
    assert "envelope points" in capsys.readouterr().out and (out / "fit.png").exists()
    bad = tmp_path / "bad.csv"
    bad.write_text("tau,A\n0,1\n2,0.9\n1,0.8\n")
    with pytest.raises(ValueError, match="bad.csv: tau must increase strictly"):
        read_time_record(bad)
    with pytest.raises(ValueError, match="--free takes one or more of lam, chi, gamma for a free decay"):
        fit_time_series(decay, TRUTH, ["Abar"])


@pytest.mark.slow  # 20 s; the free decays above keep the fit by time series in the default run
def test_a_forced_transient_gives_back_the_damping_and_its_start():
    """(45) at sigma = 3 on the Fig. 10 set from (A0, psi0) = (1.5, 0.5) onto its steady state, by
    Radau: gamma, A0 and psi0 come back to 1e-6 from four starts of the phase."""
    at = TRUTH.replace(sigma=3.0)
    tau = np.linspace(0.0, 150.0, 20)
    A, _ = _radau(at, 1.5, 0.5, tau)
    data = TimeRecord(tau, A, None, "forced")
    fit = fit_time_series(data, at.replace(gamma=0.15), ["gamma"], forced=True)
    assert fit.values["gamma"] == pytest.approx(TRUTH.gamma, rel=1e-6)
    assert fit.values["A0"] == pytest.approx(1.5, rel=1e-6)
    assert (fit.values["psi0"] - 0.5 + np.pi) % (2 * np.pi) - np.pi == pytest.approx(0.0, abs=1e-6)
    with pytest.raises(ValueError, match="a forced record needs the forcing Abar > 0"):
        fit_time_series(data, at.replace(Abar=0.0), ["gamma"], forced=True)


def _noisy(decay):
    """The Radau decay with 1 % noise of known std (seeded)."""
    rng = np.random.default_rng(5)
    std = 0.01 * decay.A
    return TimeRecord(decay.tau, decay.A + std * rng.standard_normal(len(decay.A)), std, "noisy")


@pytest.mark.slow  # 8-28 s; the file's other tests keep the capability in the default run
def test_a_decay_with_a_wrong_wall_held_is_said_not_to_fit(decay):
    """1 % noise of known std on the Radau decay, fitted with lam held at 0.6 (the truth 0.35):
    the fitted model does not describe the data, and the fit says so (naming the chi-square)."""
    wrong = fit_time_series(_noisy(decay), TRUTH.replace(gamma=0.15, lam=0.6), ["gamma"])
    assert not wrong.describes and "does not describe these data: chi-square" in wrong.goodness.statement


@pytest.mark.slow  # two more fits with their profiles
def test_a_decay_with_the_true_wall_fits_and_the_residuals_runs_catch_a_wrong_one(decay):
    """With the true lam held the chi-square's p-value is unremarkable; without the std, the wrong
    lam leaves long runs of one sign along time."""
    noisy = _noisy(decay)
    right = fit_time_series(noisy, TRUTH.replace(gamma=0.15), ["gamma"])
    assert right.describes and right.goodness.p_value > 1e-3
    blind = fit_time_series(TimeRecord(noisy.tau, noisy.A, None, "blind"), TRUTH.replace(lam=0.6), ["gamma"])
    assert blind.goodness.tests["runs_of_one_sign"] < 0.05


def test_an_elastic_wall_is_said_as_such_not_as_a_parameter_the_data_do_not_determine():
    """A decay of (45) with a nearly elastic wall (lam = 1e-4) and 1 % noise: lam's estimate sits
    at its lower end, where its relative change means nothing; the fit says the elastic wall is
    consistent with the data, not that lam is undetermined."""
    tau = np.linspace(0.0, 200.0, 25)
    A, A_min = _radau(TRUTH.replace(Abar=0.0, lam=1e-4), 3.0, 0.0, tau)
    noisy = A + np.random.default_rng(2).normal(0.0, 0.03, A.size)
    record = TimeRecord(tau[A > 1.05 * A_min], noisy[A > 1.05 * A_min], None, "elastic")
    fit = fit_time_series(record, TRUTH.replace(lam=0.2, gamma=0.15), ["lam", "gamma"])
    assert fit.estimate["lam"]["profile_95"][0] == 0.0
    assert "an elastic wall (kappa = 1) is consistent" in fit.not_identifiable
    assert "do not determine" not in fit.not_identifiable
