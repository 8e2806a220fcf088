"""The host analysis on arrays (mesoflow.analysis): each function against a closed form."""
import numpy as np
import pytest

from mesoflow import analysis


def test_beverloo_fit_recovers_its_parameters_from_exact_data():
    w = np.array([3.0, 4.0, 5.0, 6.0, 8.0, 10.0])
    Q = 2.5 * (w - 1.2) ** 1.5
    f = analysis.fit_beverloo(w, Q)
    assert f["converged"]
    assert f["beta"] == pytest.approx(1.5, rel=1e-6)
    assert f["C"] == pytest.approx(2.5, rel=1e-6)
    assert f["k"] == pytest.approx(1.2, rel=1e-5)
    with pytest.raises(ValueError):
        analysis.fit_beverloo([1.0, 2.0], [1.0, 2.0])


def test_beta_sigmoid_has_its_plateaus_and_midpoint_and_its_fit_recovers_them():
    # β = d − 1 − ½ tanh[(1/b) log10(λ/λ_c)]
    for lam, d in ((1e-3, 2), (0.3, 2), (7.0, 3)):
        assert analysis.beta_sigmoid(lam, d, 0.05, 0.5) == pytest.approx(
            d - 1 - 0.5 * np.tanh(0.5 * np.log10(lam / 0.05)), rel=1e-14)
    assert analysis.beta_sigmoid(1e-40, 2, 0.05, 0.5) == pytest.approx(1.5, abs=1e-6)
    assert analysis.beta_sigmoid(1e40, 3, 0.05, 0.5) == pytest.approx(1.5, abs=1e-6)
    assert analysis.beta_sigmoid(0.05, 3, 0.05, 0.5) == pytest.approx(2.0, abs=1e-12)
    lam = np.logspace(-4, 2, 13)
    beta = [analysis.beta_sigmoid(x, 2, 0.05, 0.4) for x in lam]
    f = analysis.fit_beta_sigmoid(lam, beta, dimension=2)
    assert f["lambda_c"] == pytest.approx(0.05, rel=1e-4)
    assert f["stretch"] == pytest.approx(0.4, rel=1e-4)


def test_permeability_theory_and_the_brinkman_fit():
    assert analysis.kappa_walls(6.0) == pytest.approx(3.0)  # H²/12
    H, B, alpha = 7.5, 0.3, 0.9
    z = np.linspace(-H / 2, H / 2, 41)
    u = [analysis.brinkman_profile(x, B, alpha, H) for x in z]
    assert u[0] == pytest.approx(0.0, abs=1e-12) and u[-1] == pytest.approx(0.0, abs=1e-12)  # no slip
    f = analysis.fit_brinkman(z, u, H)
    assert f["alpha"] == pytest.approx(alpha, rel=1e-6) and f["B"] == pytest.approx(B, rel=1e-6)
    assert analysis.mu_eff_ratio(0.2, 2.0) == pytest.approx(1 / (0.2 * 4.0))
    assert 0 < analysis.kappa_gebart_square(0.8) and 0 < analysis.kappa_sangani_acrivos_dilute(0.9)


def test_power_spectrum_puts_a_travelling_wave_in_its_bin_and_keeps_parseval():
    droplets, frames, a, dt = 16, 64, 1.0, 0.1
    k = analysis.wavenumbers(droplets, a)
    w = analysis.frequencies(frames, dt)
    p, q = 11, 40  # a wave exp[i(k_p j a − ω_q t dt)] sits in bin (p, q); its real part in (p, q) and (−p, −q)
    j, t = np.meshgrid(np.arange(droplets), np.arange(frames))
    field = np.cos(k[p] * j * a - w[q] * t * dt)
    P = analysis.power_spectrum(field, hann=False, subtract_mean=False)
    assert P.shape == (droplets, frames)
    assert np.unravel_index(np.argmax(P), P.shape) in ((p, q), (droplets - p, frames - q))
    assert P.sum() == pytest.approx(droplets * frames * (field ** 2).sum(), rel=1e-10)  # Parseval, unnormalised
    with pytest.raises(ValueError, match="frames, droplets"):
        analysis.power_spectrum(np.zeros(5))


def test_taylor_deformation_of_an_ellipse_in_the_shear_plane():
    t = np.linspace(0, 2 * np.pi, 400, endpoint=False)
    L, Bd, theta = 1.3, 0.8, 0.4  # semi-axes, inclination
    x, y = L * np.cos(t), Bd * np.sin(t)
    pts = np.c_[x * np.cos(theta) - y * np.sin(theta), x * np.sin(theta) + y * np.cos(theta), np.zeros_like(t)]
    s = analysis.shear_plane_shape(pts)
    assert s["taylor"] == pytest.approx((L - Bd) / (L + Bd), rel=1e-6)
    assert s["inclination"] == pytest.approx(theta, abs=1e-9)
