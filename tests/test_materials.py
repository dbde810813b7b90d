"""Viscoelastic materials: exact relaxation <-> creep conversion, named cases, PMMA, Prony fitting."""
import dataclasses

import numpy as np
import pytest
from scipy.integrate import quad

from framework import errors, materials
from framework.materials import (PMMA, ComplianceSeries, KelvinVoigt, Maxwell,
                                 StandardLinearSolid, Viscoelastic, fit_prony)

IDENTITY = 1e-12   # tolerance of identities and round trips (STYLE.md: ~1e-10 or better)
TIMES = np.concatenate([[0.0], np.geomspace(1e-9, 1e9, 181), [np.inf]])


def random_relaxation(rng, n):
    """``(e_inf, terms)``: times log-uniform over 1e-6..1e6 s, moduli over 1e6..1e9 Pa."""
    taus = 10.0 ** rng.uniform(-6, 6, n)
    moduli = 10.0 ** rng.uniform(6, 9, n)
    return 10.0 ** rng.uniform(6, 9), list(zip(moduli, taus))


def random_creep(rng, n):
    """``(j0, terms)``: times log-uniform over 1e-6..1e6 s, compliances over 1e-10..1e-7 1/Pa."""
    lambdas = 10.0 ** rng.uniform(-6, 6, n)
    compliances = 10.0 ** rng.uniform(-10, -7, n)
    return 10.0 ** rng.uniform(-10, -7), list(zip(compliances, lambdas))


def hereditary_identity(material, t):
    """``int_0^t E(t - s) dJ(s)`` in closed form, the jump ``E(t) J(0)`` at ``s = 0`` included.

    With ``dJ = J_k rho_k exp(-rho_k s) ds`` each product of exponentials integrates to
    ``exp(-min(r, rho) t) (1 - exp(-|r - rho| t)) / |r - rho|``.
    """
    e_inf, relaxation = material.relaxation_terms
    j0, creep = material.creep_terms
    t = np.asarray(t, dtype=float)
    total = material.relaxation(t) * j0
    for compliance, lam in creep:
        rho = 1.0 / lam
        integral = e_inf * -np.expm1(-rho * t) / rho
        for modulus, tau in relaxation:
            r = 1.0 / tau
            gap = abs(r - rho)
            integral = integral + modulus * np.exp(-min(r, rho) * t) * -np.expm1(-gap * t) / gap
        total = total + compliance * rho * integral
    return total


def assert_series_close(got, expected, rtol):
    constant, terms = got
    constant_expected, terms_expected = expected
    assert constant == pytest.approx(constant_expected, rel=rtol, abs=0)
    assert len(terms) == len(terms_expected)
    for (value, time), (value_expected, time_expected) in zip(terms, terms_expected):
        assert value == pytest.approx(value_expected, rel=rtol, abs=0)
        assert time == pytest.approx(time_expected, rel=rtol, abs=0)


def check_conversion(material):
    """J(0) E(0) = 1, J(inf) e_inf = 1 and int E dJ = 1 at every time; returns the worst error."""
    j0, creep = material.creep_terms
    errors_ = [abs(j0 * material.instantaneous_modulus - 1),
               abs(material.creep(np.inf) * material.relaxed_modulus - 1),
               abs((j0 + sum(c for c, _ in creep)) * material.e_inf - 1),
               np.max(np.abs(hereditary_identity(material, TIMES) - 1))]
    assert max(errors_) < IDENTITY, errors_
    return max(errors_)


# --------------------------------------------------------------------------- exact conversion

@pytest.mark.parametrize("n", range(1, 11))
def test_relaxation_to_creep_identities_and_round_trip(n):
    rng = np.random.default_rng(100 + n)
    for _ in range(5):
        e_inf, terms = random_relaxation(rng, n)
        material = Viscoelastic.from_prony(e_inf, terms, poisson=0.3)
        check_conversion(material)
        back = Viscoelastic.from_creep(*material.creep_terms, poisson=0.3)
        assert_series_close(back.relaxation_terms, (e_inf, tuple(sorted(terms, key=lambda p: p[1]))), IDENTITY)


@pytest.mark.parametrize("n", range(1, 11))
def test_creep_to_relaxation_identities_and_round_trip(n):
    rng = np.random.default_rng(200 + n)
    for _ in range(5):
        j0, terms = random_creep(rng, n)
        material = Viscoelastic.from_creep(j0, terms, poisson=0.3)
        assert material.creep_terms == (j0, tuple(sorted(terms, key=lambda p: p[1])))   # kept as given
        check_conversion(material)
        forward = Viscoelastic.from_prony(*material.relaxation_terms, poisson=0.3)
        assert_series_close(forward.creep_terms, material.creep_terms, IDENTITY)


@pytest.mark.parametrize("n", [1, 4, 10])
def test_roots_interlace(n):
    rng = np.random.default_rng(300 + n)
    material = Viscoelastic.from_prony(*random_relaxation(rng, n), poisson=0.25)
    relaxation_rates = np.sort(1 / material.relaxation_times)
    retardation_rates = np.sort(1 / material.retardation_times)
    # 0 < rho_1 < r_1 < rho_2 < r_2 < ... < rho_N < r_N
    merged = np.empty(2 * n)
    merged[0::2], merged[1::2] = retardation_rates, relaxation_rates
    assert merged[0] > 0 and np.all(np.diff(merged) > 0)


def test_theory_formulas_for_roots_and_residues():
    """THEORY.md sec. 4: rho_k solve e_inf - sum E_i rho/(r_i - rho) = 0 and
    D_k = 1/(rho_k sum E_i r_i/(r_i - rho_k)^2) (both confirmed)."""
    rng = np.random.default_rng(7)
    material = Viscoelastic.from_prony(*random_relaxation(rng, 6), poisson=0.3)
    e_inf, relaxation = material.relaxation_terms
    moduli = np.array([e for e, _ in relaxation])
    rates = 1 / np.array([tau for _, tau in relaxation])
    for compliance, lam in material.creep_terms[1]:
        rho = 1 / lam
        terms = moduli * rho / (rates - rho)
        assert abs(e_inf - terms.sum()) < 1e-10 * (e_inf + np.abs(terms).sum())
        assert compliance == pytest.approx(1 / (rho * np.sum(moduli * rates / (rates - rho) ** 2)), rel=1e-12)


def test_identity_by_quadrature_and_laplace_transform():
    """Two checks independent of the closed form above."""
    material = Viscoelastic.from_prony(2e9, [(5e8, 0.01), (8e8, 3.0), (3e8, 400.0)], poisson=0.4)
    j0, creep = material.creep_terms

    def creep_rate(s):
        return sum(c / lam * np.exp(-s / lam) for c, lam in creep)

    for t in [0.003, 0.5, 7.0, 90.0, 2000.0]:
        breaks = [p for p in (0.01, 0.1, 1.0, 3.0, 10.0, 100.0, 400.0, 1000.0) if p < t]
        value, _ = quad(lambda s: material.relaxation(t - s) * creep_rate(s), 0, t, points=breaks or None,
                        limit=200, epsabs=0, epsrel=1e-13)
        assert value + material.relaxation(t) * j0 == pytest.approx(1, abs=1e-11)
    e_inf, relaxation = material.relaxation_terms
    for s in np.geomspace(1e-5, 1e5, 41):
        s_relaxation = e_inf + sum(e * s / (s + 1 / tau) for e, tau in relaxation)
        s_creep = j0 + sum(c / lam / (s + 1 / lam) for c, lam in creep)
        assert s_relaxation * s_creep == pytest.approx(1, abs=1e-13)


def test_close_roots_and_wide_spectra():
    """A weak term (root next to its pole) and times over twelve decades keep full accuracy."""
    material = Viscoelastic.from_prony(1e9, [(1e3, 1e-6), (1e9, 1.0), (1e2, 1e6)], poisson=0.3)
    check_conversion(material)
    back = Viscoelastic.from_creep(*material.creep_terms, poisson=0.3)
    assert_series_close(back.relaxation_terms, material.relaxation_terms, IDENTITY)


def test_elastic_limit_and_contact_compliance():
    elastic = Viscoelastic.from_prony(3e9, [], poisson=0.3)
    assert elastic.creep_terms == (1 / 3e9, ())
    assert elastic.contact_compliance() == materials.Elastic(young=3e9, poisson=0.3).contact_compliance()
    material = Viscoelastic.from_prony(1e9, [(4e8, 50.0), (2e8, 0.5)], poisson=0.35)
    series = material.contact_compliance()
    assert type(series) is ComplianceSeries
    assert series.c0 == pytest.approx((1 - 0.35**2) / 1.6e9, rel=1e-15)
    assert series.relaxed == pytest.approx((1 - 0.35**2) / 1e9, rel=1e-13)
    np.testing.assert_allclose(series(TIMES[:-1]), (1 - 0.35**2) * material.creep(TIMES[:-1]), rtol=1e-14)
    assert material.contact_modulus == pytest.approx(1.6e9 / (1 - 0.35**2))
    assert material.instantaneous_modulus == 1.6e9 and material.relaxed_modulus == 1e9
    # stored sorted by time, whatever the input order
    assert material.terms == ((2e8, 0.5), (4e8, 50.0))
    assert material == Viscoelastic(e_inf=1e9, terms=[(2e8, 0.5), (4e8, 50.0)], poisson=0.35)
    assert np.all(np.diff(material.retardation_times) > 0)
    with pytest.raises(dataclasses.FrozenInstanceError):
        material.e_inf = 2e9


def test_vectorised_evaluation():
    t = np.geomspace(1e-2, 1e3, 12).reshape(3, 4)
    assert PMMA.relaxation(t).shape == (3, 4) and PMMA.creep(t).shape == (3, 4)
    assert np.all(np.diff(PMMA.relaxation(t.ravel())) < 0) and np.all(np.diff(PMMA.creep(t.ravel())) > 0)
    assert PMMA.relaxation(0.0) == pytest.approx(PMMA.instantaneous_modulus, rel=1e-15)


# --------------------------------------------------------------------------- named cases

def test_standard_linear_solid_closed_form():
    e_inf, e_1, tau = 1.2e9, 0.7e9, 3.5
    sls = StandardLinearSolid(e_inf, e_1, tau, poisson=0.3)
    assert isinstance(sls, Viscoelastic)
    t = TIMES[:-1]
    np.testing.assert_allclose(sls.relaxation(t), e_inf + e_1 * np.exp(-t / tau), rtol=1e-15)
    exact = 1 / e_inf - e_1 / (e_inf * (e_inf + e_1)) * np.exp(-t * e_inf / (tau * (e_inf + e_1)))
    np.testing.assert_allclose(sls.creep(t), exact, rtol=1e-14)
    assert sls.retardation_times[0] == pytest.approx(tau * (e_inf + e_1) / e_inf, rel=1e-14)


def test_maxwell_closed_forms_and_flow():
    young, tau, nu = 2e9, 5.0, 0.4
    fluid = Maxwell(young=young, relaxation_time=tau, poisson=nu)
    t = np.array([0.0, 0.1, 5.0, 100.0])
    np.testing.assert_allclose(fluid.relaxation(t), young * np.exp(-t / tau), rtol=1e-15)
    np.testing.assert_allclose(fluid.creep(t), 1 / young + t / (young * tau), rtol=1e-15)
    # int E dJ = E(t)/E + int_0^t E exp(-(t-s)/tau) / (E tau) ds = 1
    assert fluid.relaxation(t) / young + -np.expm1(-t / tau) == pytest.approx(np.ones(4), abs=1e-15)
    series = fluid.contact_compliance()
    assert isinstance(series, ComplianceSeries) and series.flow > 0
    assert series.terms == () and series.flow == pytest.approx((1 - nu**2) / (young * tau))
    np.testing.assert_allclose(series(t), (1 - nu**2) * fluid.creep(t), rtol=1e-15)
    assert series.relaxed == np.inf
    assert fluid.relaxed_modulus == 0.0 and fluid.viscosity == young * tau
    assert fluid.contact_modulus == pytest.approx(young / (1 - nu**2))


def test_kelvin_voigt_closed_forms():
    young, viscosity, nu = 1e8, 3e8, 0.45
    solid = KelvinVoigt(young=young, viscosity=viscosity, poisson=nu)
    t = np.array([0.0, 0.3, 3.0, 30.0])
    np.testing.assert_allclose(solid.creep(t), (1 - np.exp(-t * young / viscosity)) / young, rtol=1e-14)
    np.testing.assert_array_equal(solid.relaxation(t), young)   # regular part; eta delta(t) left out
    series = solid.contact_compliance()
    assert series.c0 == 0.0 and series.terms == (((1 - nu**2) / young, 3.0),)
    assert solid.creep_terms == (0.0, ((1 / young, 3.0),))
    assert solid.instantaneous_modulus == np.inf and solid.relaxed_modulus == young


# --------------------------------------------------------------------------- PMMA of seed 001

def seed_001_printed_creep(t):
    """Seed 001 eq. 4 [1/MPa], converted to 1/Pa."""
    return (7e-4 - 6.17e-5 * np.exp(-0.1 * t) - 8.38e-5 * np.exp(-7.47e-3 * t)) * 1e-6


def test_pmma_relaxation_modulus():
    t = np.array([0.0, 10.0, 1000.0])
    mpa = 1973 + 254.776 * np.exp(-t / 8.93) + 263.6628 * np.exp(-t / 117.96)
    np.testing.assert_allclose(PMMA.relaxation(t), mpa * 1e6, rtol=1e-15)
    assert PMMA.poisson == 0.35
    check_conversion(PMMA)


def test_pmma_exact_creep_and_the_printed_one():
    # exact retardation times (seed 001 prints 10 s and 133.9 s)
    np.testing.assert_allclose(PMMA.retardation_times, [9.93630, 133.870], rtol=1e-5)
    j0, ((j_fast, _), (j_slow, _)) = PMMA.creep_terms
    assert j0 * 1e6 == pytest.approx(4.01374e-4, rel=1e-5)
    assert (j_fast * 1e6, j_slow * 1e6) == pytest.approx((4.47406e-5, 6.07272e-5), rel=1e-5)
    # the printed creep is 1.381 times too large at every time: measured 1.38098..1.38150
    t = np.concatenate([[0.0], np.linspace(0, 2000, 20001)[1:], [1e4, 1e6, np.inf]])
    ratio = seed_001_printed_creep(t) / PMMA.creep(t)
    assert ratio[0] == pytest.approx(1.38150, abs=1e-5)
    assert ratio[-1] == pytest.approx(7e-4 * 1973, rel=1e-12)
    assert 1.3809 < ratio.min() and ratio.max() < 1.3816


# --------------------------------------------------------------------------- fitting

KNOWN = Viscoelastic.from_prony(1e9, [(3e8, 0.1), (2e8, 10.0), (4e8, 1000.0)], poisson=0.35)
SAMPLES = np.concatenate([[0.0], np.geomspace(1e-3, 1e4, 141)])


def test_fit_recovers_a_known_series_on_its_own_times():
    fit = fit_prony(SAMPLES, KNOWN.relaxation(SAMPLES), "relaxation", times=KNOWN.relaxation_times, poisson=0.35)
    assert_series_close((fit.constant, fit.terms), KNOWN.relaxation_terms, 1e-10)
    assert fit.max_relative_error < 1e-12 and fit.material.poisson == 0.35
    fit = fit_prony(SAMPLES, KNOWN.creep(SAMPLES), kind="creep", times=KNOWN.retardation_times, poisson=0.35)
    assert_series_close((fit.constant, fit.terms), KNOWN.creep_terms, 1e-10)
    assert_series_close(fit.material.relaxation_terms, KNOWN.relaxation_terms, 1e-9)
    assert fit.max_relative_error < 1e-12


@pytest.mark.parametrize("kind", ["relaxation", "creep"])
def test_fit_on_a_log_grid_reports_its_error(kind):
    """Grid times that miss the true ones: a few per mille, and the reported errors are the true ones."""
    t = np.concatenate([[0.0], np.geomspace(2e-3, 3e4, 150)])
    data = KNOWN.relaxation(t) if kind == "relaxation" else KNOWN.creep(t)
    fit = fit_prony(t, data, kind, n_terms=22, poisson=0.35)
    assert np.allclose(fit.times, np.geomspace(2e-3, 3e4, 22))
    model = fit.material.relaxation(t) if kind == "relaxation" else fit.material.creep(t)
    np.testing.assert_allclose(model, fit.fitted, rtol=1e-10)
    assert fit.max_relative_error == pytest.approx(np.max(np.abs(model / data - 1)), rel=1e-6)
    assert fit.rms_error == pytest.approx(np.sqrt(np.mean((model - data) ** 2)), rel=1e-6)
    assert 0 < fit.max_relative_error < 1e-2
    coarse = fit_prony(t, data, kind, n_terms=8, poisson=0.35)
    assert coarse.max_relative_error > fit.max_relative_error   # more terms, smaller error
    assert len(fit_prony(t, data, kind, poisson=0.35).times) == 8  # default: one per decade


# --------------------------------------------------------------------------- bad input

@pytest.mark.parametrize("terms, message", [
    ([(1e8, 2.0), (1e8, -3.0)], r"terms\[1\] relaxation time must be positive \[s\], got -3.0"),
    ([(1e8, 0.0)], r"terms\[0\] relaxation time must be positive \[s\], got 0.0"),
    ([(-1e8, 2.0)], r"terms\[0\] modulus must be positive \[Pa\], got -100000000.0"),
    ([(0.0, 2.0)], r"terms\[0\] modulus must be positive \[Pa\], got 0.0"),
    ([(float("nan"), 2.0)], r"terms\[0\] modulus must be a finite real number, got nan"),
    ([(1e8, float("inf"))], r"terms\[0\] relaxation time must be a finite real number, got inf"),
    ([(1e8, 2.0), (3e8, 2.0)], r"terms\[1\] relaxation time must differ .* got 2.0 s, the same as terms\[0\]"),
    ([(1e8, 2.0, 3.0)], r"terms\[0\] must be a \(modulus \[Pa\], relaxation time \[s\]\) pair, got"),
    (5.0, r"terms must be a sequence of \(modulus \[Pa\], relaxation time \[s\]\) pairs, got 5.0"),
])
def test_bad_relaxation_terms(terms, message):
    with pytest.raises(errors.ParameterError, match=message):
        Viscoelastic.from_prony(1e9, terms, poisson=0.3)


@pytest.mark.parametrize("e_inf, message", [
    (0.0, r"e_inf must be positive \[Pa\], got 0.0; .* fluid: use materials.Maxwell"),
    (-1e9, r"e_inf must be positive \[Pa\], got -1000000000.0"),
    (float("inf"), r"e_inf must be a finite real number, got inf"),
])
def test_bad_relaxed_modulus(e_inf, message):
    with pytest.raises(errors.ParameterError, match=message):
        Viscoelastic.from_prony(e_inf, [(1e8, 1.0)], poisson=0.3)


@pytest.mark.parametrize("poisson", [0.6, -1.0, float("nan")])
def test_bad_poisson(poisson):
    with pytest.raises(errors.ParameterError, match=r"poisson must"):
        Viscoelastic.from_prony(1e9, [(1e8, 1.0)], poisson=poisson)
    with pytest.raises(errors.ParameterError, match=r"poisson must"):
        Viscoelastic.from_creep(1e-9, [(1e-10, 1.0)], poisson=poisson)


@pytest.mark.parametrize("j0, terms, message", [
    (0.0, [(1e-10, 1.0)], r"j0 must be positive \[1/Pa\], got 0.0; .*use materials.KelvinVoigt"),
    (1e-9, [(-1e-10, 1.0)], r"terms\[0\] compliance must be positive \[1/Pa\], got -1e-10"),
    (1e-9, [(1e-10, 1.0), (1e-10, -2.0)], r"terms\[1\] retardation time must be positive \[s\], got -2.0"),
    (1e-9, [(1e-10, 1.0), (2e-10, 1.0)], r"terms\[1\] retardation time must differ"),
])
def test_bad_creep_terms(j0, terms, message):
    with pytest.raises(errors.ParameterError, match=message):
        Viscoelastic.from_creep(j0, terms, poisson=0.3)


def test_bad_named_cases_and_times():
    with pytest.raises(errors.ParameterError, match=r"e_1 must be positive \[Pa\], got -1.0"):
        StandardLinearSolid(1e9, -1.0, 2.0, poisson=0.3)
    with pytest.raises(errors.ParameterError, match=r"tau must be positive \[s\], got 0.0"):
        StandardLinearSolid(1e9, 1e8, 0.0, poisson=0.3)
    with pytest.raises(errors.ParameterError, match=r"e_inf must be positive .*Maxwell"):
        StandardLinearSolid(0.0, 1e8, 1.0, poisson=0.3)
    with pytest.raises(errors.ParameterError, match=r"relaxation_time must be positive \[s\], got -5.0"):
        Maxwell(young=1e9, relaxation_time=-5.0, poisson=0.3)
    with pytest.raises(errors.ParameterError, match=r"viscosity must be positive \[Pa s\], got 0.0"):
        KelvinVoigt(young=1e9, viscosity=0.0, poisson=0.3)
    with pytest.raises(errors.ParameterError, match=r"young must be positive \[Pa\], got -1.0"):
        KelvinVoigt(young=-1.0, viscosity=1e9, poisson=0.3)
    with pytest.raises(errors.ParameterError, match=r"t must be >= 0 \[s\] .*got -1.0 at index \(1,\)"):
        PMMA.creep([0.0, -1.0])
    with pytest.raises(errors.ParameterError, match=r"t must be >= 0 \[s\] .*got nan"):
        Maxwell(young=1e9, relaxation_time=1.0, poisson=0.3).relaxation(float("nan"))


@pytest.mark.parametrize("t, values, kwargs, error, message", [
    ([0, 2, 1, 3], [4, 3, 2, 1], {}, errors.ParameterError,
     r"t must be strictly increasing, got t\[2\] = 1.0 after t\[1\] = 2.0"),
    ([0, 1, 1, 3], [4, 3, 2, 1], {}, errors.ParameterError,
     r"t must be strictly increasing, got t\[2\] = 1.0 after t\[1\] = 1.0"),
    ([-1, 1, 2, 3], [4, 3, 2, 1], {}, errors.ParameterError, r"t must be >= 0 \[s\], got t\[0\] = -1.0"),
    ([0, 1, 2, 3], [4, -3, 2, 1], {}, errors.ParameterError, r"values must be positive .*got values\[1\] = -3.0"),
    ([0, 1, 2, 3], [4, 3, 2], {}, errors.ShapeError, r"values has 3 samples but t has 4"),
    ([0, 1, 2, 3], [4, 3, 2, 1], {"kind": "shear"}, errors.ParameterError,
     r"kind must be 'relaxation', 'creep' or 'dynamic', got 'shear'"),
    ([0, 1, 2, 3], [4, 3, 2, 1], {"n_terms": 0}, errors.ParameterError, r"n_terms must be an integer >= 1, got 0"),
    ([0, 1, 2, 3], [4, 3, 2, 1], {"n_terms": 5}, errors.ParameterError,
     r"5 Prony times and a constant need at least 6 samples, got 4"),
    ([0, 1, 2, 3], [4, 3, 2, 1], {"times": [1.0, -2.0]}, errors.ParameterError,
     r"times\[1\] must be positive \[s\], got -2.0"),
    ([0, 1, 2, 3], [4, 3, 2, 1], {"poisson": 0.7}, errors.ParameterError, r"poisson must lie in"),
    ([0, 1, 2, float("nan")], [4, 3, 2, 1], {}, errors.ParameterError, r"t must be finite everywhere, got nan"),
])
def test_bad_fit_input(t, values, kwargs, error, message):
    kwargs = {"poisson": 0.3, **kwargs}
    with pytest.raises(error, match=message):
        fit_prony(t, values, **kwargs)


def test_fit_needs_poisson_and_rejects_a_fluid():
    t = np.linspace(0, 10, 50)
    with pytest.raises(TypeError, match="poisson"):
        fit_prony(t, np.exp(-t), "relaxation", 3)
    with pytest.raises(errors.ParameterError, match=r"fitted e_inf is 0.0; .*Maxwell"):
        fit_prony(t, 1e9 * np.exp(-t / 0.5), "relaxation", times=[0.5], poisson=0.3)
