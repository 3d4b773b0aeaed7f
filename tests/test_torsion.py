"""The equivalent torsional chain: closed forms, an independent eigensolver, OpenTorsion's
finite-element model, mode shapes and the forced response.

Closed forms: two discs, ω² = c (J₁ + J₂)/(J₁J₂); a free uniform chain of n discs,
ω_k = 2√(c/J) sin(kπ/2n); a uniform chain with one end grounded,
ω_k = 2√(c/J) sin((2k − 1)π/(2(2n + 1))); one disc on a grounded shaft, the steady amplitude
T/|c − Ω²J + iΩC|.
"""
import numpy as np
import pytest
import scipy.linalg
from numpy.testing import assert_allclose

from processing.synth.torsiograph import Crankshaft
from processing.torsional.chain import chain_matrices, forced_response, natural_modes

CRANKSHAFT = Crankshaft()


def test_two_discs_closed_form():
    J1, J2, c = 0.05, 1.3, 5.2e5
    m = natural_modes([J1, J2], [c])
    assert m.angular_frequency.shape == (1,)
    assert m.angular_frequency[0] ** 2 == pytest.approx(c * (J1 + J2) / (J1 * J2), rel=1e-12)
    # the discs swing against each other, amplitudes inversely as their inertias
    assert m.relative()[1, 0] == pytest.approx(-J1 / J2, rel=1e-12)


@pytest.mark.parametrize("n", [2, 3, 6, 11])
def test_free_uniform_chain_closed_form(n):
    J, c = 0.035, 7.8e5
    m = natural_modes(np.full(n, J), np.full(n - 1, c))
    k = np.arange(1, n)
    assert_allclose(m.angular_frequency, 2 * np.sqrt(c / J) * np.sin(k * np.pi / (2 * n)),
                    rtol=1e-12)


@pytest.mark.parametrize("n", [1, 4, 7])
def test_grounded_uniform_chain_closed_form(n):
    J, c = 0.2, 3e5
    m = natural_modes(np.full(n, J), np.full(n, c))
    k = np.arange(1, n + 1)
    assert_allclose(m.angular_frequency,
                    2 * np.sqrt(c / J) * np.sin((2 * k - 1) * np.pi / (2 * (2 * n + 1))),
                    rtol=1e-12)


def test_against_scipy_generalised_eigensolver():
    M, K, _ = chain_matrices(CRANKSHAFT.inertia, CRANKSHAFT.stiffness)
    lam = scipy.linalg.eigh(K, M, eigvals_only=True)[1:]
    m = natural_modes(CRANKSHAFT.inertia, CRANKSHAFT.stiffness)
    assert_allclose(m.angular_frequency, np.sqrt(lam), rtol=1e-10)


def test_against_opentorsion_finite_element_model():
    """OpenTorsion (an independent finite-element code) assembles the same chain from shaft
    elements and disks: the natural frequencies agree to 0.1 % (the issue's target), in fact
    to rounding."""
    ot = pytest.importorskip("opentorsion")
    J, c = CRANKSHAFT.inertia, CRANKSHAFT.stiffness
    shafts = [ot.Shaft(i, i + 1, k=k, I=0.0) for i, k in enumerate(c)]
    disks = [ot.Disk(i, I=j) for i, j in enumerate(J)]
    lam, _ = ot.Assembly(shafts, disk_elements=disks).undamped_modal_analysis()
    omega = np.sort(np.sqrt(np.abs(lam.real)))[1:]
    assert_allclose(natural_modes(J, c).angular_frequency, omega, rtol=1e-3)
    assert_allclose(natural_modes(J, c).angular_frequency, omega, rtol=1e-9)


def test_mode_shapes_are_mass_orthonormal_and_signed_at_the_reference():
    J, c = np.asarray(CRANKSHAFT.inertia), np.asarray(CRANKSHAFT.stiffness)
    m = natural_modes(J, c, reference=0)
    v = m.shape
    assert_allclose(v.T @ np.diag(J) @ v, np.eye(v.shape[1]), atol=1e-10)
    M, K, _ = chain_matrices(J, c)
    assert_allclose(K @ v, M @ v * m.angular_frequency ** 2, rtol=1e-8, atol=1e-6)
    assert np.all(v[0] > 0)
    assert_allclose(m.relative()[0], 1.0)
    # the first mode of a crankshaft with a heavy flywheel: the flywheel hardly moves
    assert abs(m.relative()[-1, 0]) < 0.1


def test_a_stack_of_chains_is_solved_in_one_call():
    rng = np.random.default_rng(3)
    J = np.asarray(CRANKSHAFT.inertia) * (1 + 0.02 * rng.standard_normal((5, 6)))
    c = np.asarray(CRANKSHAFT.stiffness) * (1 + 0.02 * rng.standard_normal((5, 5)))
    stacked = natural_modes(J, c).angular_frequency
    one_by_one = np.array([natural_modes(j, k).angular_frequency for j, k in zip(J, c)])
    assert_allclose(stacked, one_by_one, rtol=1e-12)


def test_single_disc_forced_response_closed_form():
    J, c, C, T = 0.5, 2e4, 3.0, 10.0
    omega = np.array([50.0, 200.0, 400.0])
    theta = forced_response([J], [c], [T], omega, damping=[C])[:, 0]
    assert_allclose(theta, T / (c - omega ** 2 * J + 1j * omega * C), rtol=1e-12)


def test_forced_response_peaks_at_the_natural_frequency_of_a_lightly_damped_chain():
    J, c = CRANKSHAFT.inertia, CRANKSHAFT.stiffness
    f1 = natural_modes(J, c).angular_frequency[0]
    omega = np.linspace(0.8, 1.2, 4001) * f1
    torque = np.zeros(6)
    torque[1] = 100.0
    nose = np.abs(forced_response(J, c, torque, omega, damping=[0.5] * 6)[:, 0])
    assert omega[np.argmax(nose)] == pytest.approx(f1, rel=2e-4)


def test_free_chain_rigid_rotation_under_a_steady_torque_sum():
    """A free chain driven by torques that sum to T swings as a rigid body at low frequency,
    θ ≈ −T/(J_total Ω²)."""
    J, c = CRANKSHAFT.inertia, CRANKSHAFT.stiffness
    torque = np.array([0, 25.0, 25.0, 25.0, 25.0, 0])
    omega = 2.0
    theta = forced_response(J, c, torque, [omega])[0]
    assert_allclose(theta, -100.0 / (sum(J) * omega ** 2), rtol=1e-3)


@pytest.mark.parametrize("J, c, match", [
    ([1.0, -1.0], [10.0], "inertia"),
    ([1.0, 1.0], [0.0], "stiffness"),
    ([1.0, 1.0, 1.0], [10.0], "shaft stiffnesses"),
    ([1.0], [], "single free disc"),
])
def test_bad_chains_are_refused(J, c, match):
    with pytest.raises(ValueError, match=match):
        natural_modes(J, c)


@pytest.mark.parametrize("n, k", [(10, 3), (11, 4), (1000, 250), (40_000, 571), (40_000, 570)])
def test_the_slow_parts_moving_average_is_numpys_convolution(n, k):
    """By running sums, to rounding: the mean over k samples about each, zeros beyond."""
    from processing.torsional.seismic import _moving_average

    x = np.random.default_rng(n + k).standard_normal(n) + 5.0
    assert np.allclose(_moving_average(x, k), np.convolve(x, np.ones(k) / k, mode="same"),
                       rtol=0, atol=1e-13)
