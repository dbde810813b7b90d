"""Independent checks of the analytic reference solutions in framework.reference.

Nothing here re-types a formula of the modules under test: each pressure is
integrated to its load, and its surface displacement, computed by quadrature
of the Boussinesq (half-space) kernels, is compared with the rigid-body
motion minus the indenter profile.
"""
import numpy as np
import pytest
from scipy.integrate import quad
from scipy.special import ellipe, ellipkm1

from framework.reference.hertz import HertzCylinder, HertzSphere
from framework.reference.punch import FlatPunch, RoundedFlatPunch
from framework.reference.westergaard import Westergaard

CONTACT_MODULUS = 2.1e11 / (1.0 - 0.3**2)  # steel [Pa]


def integrate(function, breaks, singular=()):
    """Adaptive quadrature of ``function`` over sorted ``breaks``, split at each of them.

    Next to a point of ``singular`` (a logarithmic singularity, itself a
    break) the piece is mapped by x = x_s +- L w**2, so that the integrand
    becomes w ln(w): continuous, and never evaluated at the singular point.
    """
    points = np.unique(np.asarray([*breaks, *singular], dtype=float))
    total = 0.0
    for low, high in zip(points[:-1], points[1:]):
        length = high - low
        if low in singular and high in singular:
            middle = 0.5 * (low + high)
            total += integrate(function, [low, middle, high], singular)
            continue
        if low in singular:
            def mapped(w, low=low, length=length):
                return function(low + length * w * w) * 2.0 * length * w
        elif high in singular:
            def mapped(w, high=high, length=length):
                return function(high - length * w * w) * 2.0 * length * w
        else:
            def mapped(w, low=low, length=length):
                return function(low + length * w) * length
        total += quad(mapped, 0.0, 1.0, epsabs=0.0, epsrel=1e-12, limit=400)[0]
    return total


def axisymmetric_integral(function, radius, breaks=(), singular=()):
    """int_0^a function(s) ds with s = a sin(theta), which smooths the edge behaviour at s = a.

    ``breaks`` and ``singular`` (log singularities) are radii where the quadrature is split.
    """
    def angle(s):
        return np.arcsin(min(s / radius, 1.0))

    def in_angle(theta):
        return function(radius * np.sin(theta)) * radius * np.cos(theta)

    return integrate(in_angle, [0.0, 0.5 * np.pi] + [angle(b) for b in breaks],
                     [angle(s) for s in singular])


def axisymmetric_load(pressure, radius, breaks=()):
    """W = int_0^a 2 pi s p(s) ds [N]."""
    return axisymmetric_integral(lambda s: 2.0 * np.pi * s * pressure(s), radius, breaks)


def centre_displacement(pressure, radius, breaks=()):
    """Boussinesq: u3(0) = (2 / E*) int_0^a p(s) ds [m]."""
    return 2.0 / CONTACT_MODULUS * axisymmetric_integral(pressure, radius, breaks)


def axisymmetric_displacement(pressure, r, radius, breaks=()):
    """u3(r) = (4 / (pi E*)) int_0^a p(s) s K(k) / (r + s) ds, k = 2 sqrt(r s) / (r + s).

    The ring kernel int_0^2pi dphi / |x - y| = 4 K(k) / (r + s); scipy's
    elliptic functions take the parameter m = k**2 (ellipkm1 takes 1 - m).
    The log singularity at s = r is handled by ``integrate``.
    """
    def integrand(s):
        # ellipkm1 takes 1 - m = ((r - s) / (r + s))**2, accurate next to s = r
        return pressure(s) * s * ellipkm1(((r - s) / (r + s)) ** 2) / (r + s)

    return 4.0 / (np.pi * CONTACT_MODULUS) * axisymmetric_integral(integrand, radius, breaks, (r,))


def antisymmetric_displacement(pressure_amplitude, r, radius):
    """u3(r, phi=0) under p(s, phi) = pressure_amplitude(s) cos(phi).

    int_0^2pi cos(phi) dphi / |x - y| = 4 ((2 - k**2) K(k) - 2 E(k)) / (k**2 (r + s)).
    """
    def integrand(s):
        complement = ((r - s) / (r + s)) ** 2  # 1 - m, so that m = k**2 <= 1 exactly
        parameter = 1.0 - complement
        if parameter < 1e-6:  # small-k series, avoids 0/0
            ring_over_parameter = np.pi * parameter / 16.0
        else:
            ring_over_parameter = ((2.0 - parameter) * ellipkm1(complement)
                                   - 2.0 * ellipe(parameter)) / parameter
        return pressure_amplitude(s) * s * 4.0 * ring_over_parameter / (r + s)

    return 1.0 / (np.pi * CONTACT_MODULUS) * axisymmetric_integral(integrand, radius, (), (r,))


# --------------------------------------------------------------------------- Hertz sphere

@pytest.fixture
def sphere():
    return HertzSphere(radius=0.01, load=100.0, contact_modulus=CONTACT_MODULUS)


def test_sphere_pressure_integrates_to_load(sphere):
    load = axisymmetric_load(sphere.pressure, sphere.contact_radius)
    assert load == pytest.approx(sphere.load, rel=1e-10)
    assert sphere.mean_pressure * np.pi * sphere.contact_radius**2 == pytest.approx(sphere.load, rel=1e-14)


def test_sphere_approach_is_centre_displacement(sphere):
    approach = centre_displacement(sphere.pressure, sphere.contact_radius)
    assert approach == pytest.approx(sphere.approach, rel=1e-10)


@pytest.mark.parametrize("fraction", [0.1, 0.4, 0.7, 0.95])
def test_sphere_surface_displacement_fits_profile(sphere, fraction):
    r = fraction * sphere.contact_radius
    displacement = axisymmetric_displacement(sphere.pressure, r, sphere.contact_radius)
    expected = sphere.approach - r**2 / (2.0 * sphere.radius)
    assert displacement == pytest.approx(expected, rel=1e-8)


def test_sphere_from_contact_radius_round_trip(sphere):
    copy = HertzSphere.from_contact_radius(sphere.radius, sphere.contact_radius, CONTACT_MODULUS)
    assert copy.load == pytest.approx(sphere.load, rel=1e-13)


def test_sphere_max_shear_on_axis(sphere):
    max_shear, depth = sphere.max_shear_on_axis(0.3)
    assert max_shear / sphere.max_pressure == pytest.approx(0.31002, abs=1e-4)
    assert depth / sphere.contact_radius == pytest.approx(0.48086, abs=1e-4)


@pytest.mark.parametrize("depth_ratio", [0.3, 1.0, 2.5])
def test_sphere_axis_stress_against_boussinesq(sphere, depth_ratio):
    """Superpose point-force (Boussinesq) stresses over the Hertz pressure.

    A point force P at horizontal distance r and depth z (rho**2 = r**2 + z**2)
    gives s_zz = -3 P z**3 / (2 pi rho**5) and s_rr + s_tt = (P / 2 pi)
    ((1 - 2 nu) z / rho**3 - 3 z r**2 / rho**5) (Johnson 1985, section 3.2; its
    trace with s_zz is the known -(1 + nu) P z / (pi rho**3)). A ring of force
    acts on the axis with s11 = s22 = (s_rr + s_tt) / 2.
    """
    poisson = 0.3
    z = depth_ratio * sphere.contact_radius
    radius = sphere.contact_radius

    def axial(s):
        return -3.0 * sphere.pressure(s) * z**3 * s / (s**2 + z**2) ** 2.5

    def radial(s):
        rho_squared = s**2 + z**2
        return 0.5 * sphere.pressure(s) * s * ((1.0 - 2.0 * poisson) * z / rho_squared**1.5
                                               - 3.0 * z * s**2 / rho_squared**2.5)

    radial_stress, axial_stress = sphere.axis_stress(z, poisson)
    assert axial_stress == pytest.approx(axisymmetric_integral(axial, radius), rel=1e-10)
    assert radial_stress == pytest.approx(axisymmetric_integral(radial, radius), rel=1e-10)


def test_sphere_axis_stress_at_surface(sphere):
    radial, axial = sphere.axis_stress(np.array([0.0]), 0.3)
    assert axial[0] == pytest.approx(-sphere.max_pressure, rel=1e-14)
    assert radial[0] == pytest.approx(-(0.5 + 0.3) * sphere.max_pressure, rel=1e-14)


# --------------------------------------------------------------------------- Hertz cylinder

@pytest.fixture
def cylinder():
    return HertzCylinder(radius=0.02, load_per_length=1e5, contact_modulus=CONTACT_MODULUS)


def test_cylinder_pressure_integrates_to_load(cylinder):
    b = cylinder.half_width
    load = integrate(lambda theta: cylinder.pressure(b * np.sin(theta)) * b * np.cos(theta),
                     [-0.5 * np.pi, 0.5 * np.pi])
    assert load == pytest.approx(cylinder.load_per_length, rel=1e-10)


def test_cylinder_surface_displacement_fits_profile(cylinder):
    """Plane strain: u3(x) = -(2 / (pi E*)) int p(s) ln|x - s| ds + const = delta - x**2 / (2 R)."""
    b = cylinder.half_width

    def displacement(x):
        def integrand(theta):
            s = b * np.sin(theta)
            return cylinder.pressure(s) * np.log(abs(x - s)) * b * np.cos(theta)
        return -2.0 / (np.pi * CONTACT_MODULUS) * integrate(
            integrand, [-0.5 * np.pi, 0.5 * np.pi], [np.arcsin(x / b)])

    centre = displacement(0.0)
    for fraction in (-0.8, 0.3, 0.6, 0.97):
        x = fraction * b
        assert displacement(x) - centre == pytest.approx(-x**2 / (2.0 * cylinder.radius), rel=1e-8)


# --------------------------------------------------------------------------- flat punch

@pytest.fixture
def flat_punch():
    return FlatPunch(radius=1e-3, contact_modulus=CONTACT_MODULUS)


def test_flat_punch_pressure_integrates_to_load(flat_punch):
    load = axisymmetric_load(lambda r: flat_punch.pressure(r, 50.0), flat_punch.radius)
    assert load == pytest.approx(50.0, rel=1e-8)


def test_flat_punch_approach_and_displacement(flat_punch):
    load = 50.0

    def pressure(r):
        return flat_punch.pressure(r, load)

    approach = flat_punch.approach(load)
    assert centre_displacement(pressure, flat_punch.radius) == pytest.approx(approach, rel=1e-8)
    for fraction in (0.2, 0.6, 0.9):
        displacement = axisymmetric_displacement(pressure, fraction * flat_punch.radius, flat_punch.radius)
        assert displacement == pytest.approx(approach, rel=1e-8)


def test_flat_punch_tilt(flat_punch):
    """Pressure C r cos(phi) / sqrt(a**2 - r**2) has moment M and tilts the face rigidly by theta."""
    moment, a = 0.02, flat_punch.radius
    amplitude = 3.0 * moment / (2.0 * np.pi * a**3)

    def pressure_amplitude(s):
        return amplitude * s / np.sqrt(a**2 - s**2)

    # M = int int p x dA = pi int_0^a p1(s) s**2 ds
    total_moment = np.pi * axisymmetric_integral(lambda s: pressure_amplitude(s) * s**2, a)
    assert total_moment == pytest.approx(moment, rel=1e-8)
    tilt = flat_punch.tilt(moment)
    for fraction in (0.1, 0.5, 0.85):
        r = fraction * a
        assert antisymmetric_displacement(pressure_amplitude, r, a) / r == pytest.approx(tilt, rel=1e-7)


# --------------------------------------------------------------------------- rounded flat punch

EDGE_RADIUS = 5e-3
CONTACT_RADIUS = 1e-3


def rounded_punch(flat_ratio):
    return RoundedFlatPunch(flat_radius=flat_ratio * CONTACT_RADIUS, edge_radius=EDGE_RADIUS,
                            contact_modulus=CONTACT_MODULUS)


@pytest.mark.parametrize("flat_ratio", [0.2, 0.5, 0.8])
def test_rounded_punch_load_and_approach(flat_ratio):
    punch = rounded_punch(flat_ratio)

    def pressure(r):
        return punch.pressure(r, CONTACT_RADIUS)

    breaks = (punch.flat_radius,)
    load = axisymmetric_load(pressure, CONTACT_RADIUS, breaks)
    assert load == pytest.approx(punch.load(CONTACT_RADIUS), rel=1e-8)
    approach = centre_displacement(pressure, CONTACT_RADIUS, breaks)
    assert approach == pytest.approx(punch.approach(CONTACT_RADIUS), rel=1e-8)
    assert punch.contact_radius(punch.load(CONTACT_RADIUS)) == pytest.approx(CONTACT_RADIUS, rel=1e-12)


@pytest.mark.parametrize("flat_ratio", [0.2, 0.5, 0.8])
def test_rounded_punch_surface_displacement_fits_profile(flat_ratio):
    punch = rounded_punch(flat_ratio)
    approach = punch.approach(CONTACT_RADIUS)
    for fraction in (0.1, 0.45, 0.65, 0.9):
        r = fraction * CONTACT_RADIUS
        displacement = axisymmetric_displacement(lambda s: punch.pressure(s, CONTACT_RADIUS), r,
                                                 CONTACT_RADIUS, (punch.flat_radius,))
        assert displacement == pytest.approx(approach - punch.profile(r), rel=1e-7)


def test_rounded_punch_tends_to_hertz():
    punch = rounded_punch(1e-9)
    hertz = HertzSphere.from_contact_radius(EDGE_RADIUS, CONTACT_RADIUS, CONTACT_MODULUS)
    assert punch.load(CONTACT_RADIUS) == pytest.approx(hertz.load, rel=1e-8)
    assert punch.approach(CONTACT_RADIUS) == pytest.approx(hertz.approach, rel=1e-8)
    r = np.linspace(0.0, 0.99, 7) * CONTACT_RADIUS
    np.testing.assert_allclose(punch.pressure(r, CONTACT_RADIUS), hertz.pressure(r), rtol=1e-7)
    assert punch.contact_radius(hertz.load) == pytest.approx(CONTACT_RADIUS, rel=1e-8)


def test_rounded_punch_load_increases():
    punch = rounded_punch(0.5)
    radii = punch.flat_radius * np.linspace(1.0, 10.0, 200)
    loads = np.array([punch.load(a) for a in radii])
    assert loads[0] == pytest.approx(0.0, abs=1e-30)
    assert np.all(np.diff(loads) > 0.0)


@pytest.mark.parametrize("flat_ratio", [0.2, 0.5, 0.8])
def test_rounded_punch_pressure_is_finite_and_vanishes_at_edge(flat_ratio):
    punch = rounded_punch(flat_ratio)
    r = np.linspace(0.0, 1.0, 101) * CONTACT_RADIUS
    pressure = punch.pressure(r, CONTACT_RADIUS)
    assert np.all(np.isfinite(pressure))
    assert np.all(pressure[:-1] > 0.0)
    assert pressure[-1] == 0.0
    # square-root edge: p(a (1 - e)) / sqrt(e) tends to a finite limit
    ratios = [punch.pressure(CONTACT_RADIUS * (1.0 - e), CONTACT_RADIUS) / np.sqrt(e) for e in (1e-6, 1e-8)]
    assert ratios[1] == pytest.approx(ratios[0], rel=1e-5)
    assert ratios[0] < 10.0 * pressure.max()


# --------------------------------------------------------------------------- Westergaard

@pytest.fixture
def wavy():
    return Westergaard(amplitude=1e-6, wavelength=1e-4, contact_modulus=CONTACT_MODULUS)


@pytest.mark.parametrize("load_ratio", [0.1, 0.5, 0.9, 1.0, 1.5])
def test_westergaard_mean_pressure(wavy, load_ratio):
    mean_pressure = load_ratio * wavy.full_contact_pressure
    a = wavy.contact_half_width(mean_pressure)
    # integrate over one period [a - lambda, a] with s = a sin(theta) on the contact
    contact = integrate(lambda theta: wavy.pressure(a * np.sin(theta), mean_pressure) * a * np.cos(theta),
                        [-0.5 * np.pi, 0.5 * np.pi])
    gap = integrate(lambda x: wavy.pressure(x, mean_pressure), [a, wavy.wavelength - a])
    assert (contact + gap) / wavy.wavelength == pytest.approx(mean_pressure, rel=1e-10)
    x = np.linspace(-0.5, 0.5, 101) * wavy.wavelength
    pressure = wavy.pressure(x, mean_pressure)
    assert pressure.argmax() == 50  # highest where h is lowest, x = 0
    np.testing.assert_allclose(wavy.pressure(x + wavy.wavelength, mean_pressure), pressure,
                               atol=1e-7 * pressure.max())  # sqrt(rounding) at a contact edge


def test_westergaard_full_contact_displacement_by_fft(wavy):
    """Periodic half-space: u_hat = 2 p_hat / (E* |k|), k != 0; u + h must be uniform."""
    count = 256
    x = np.arange(count) * wavy.wavelength / count
    for load_ratio in (1.0, 2.0):
        pressure = wavy.pressure(x, load_ratio * wavy.full_contact_pressure)
        assert pressure.min() >= -1e-9 * wavy.full_contact_pressure
        wavenumber = 2.0 * np.pi * np.abs(np.fft.fftfreq(count, d=wavy.wavelength / count))
        pressure_hat = np.fft.fft(pressure)
        displacement_hat = np.zeros_like(pressure_hat)
        displacement_hat[1:] = 2.0 * pressure_hat[1:] / (CONTACT_MODULUS * wavenumber[1:])
        displacement = np.fft.ifft(displacement_hat).real
        rigid = displacement + wavy.profile(x)
        assert np.ptp(rigid) < 1e-12 * wavy.amplitude


@pytest.mark.parametrize("load_ratio", [0.1, 0.5, 0.9])
def test_westergaard_partial_contact_displacement(wavy, load_ratio):
    """Periodic line-load kernel: u3(x) = -(2 / (pi E*)) int p(s) ln|2 sin(pi (x - s) / lambda)| ds."""
    mean_pressure = load_ratio * wavy.full_contact_pressure
    a = wavy.contact_half_width(mean_pressure)
    wavelength = wavy.wavelength

    def displacement(x):
        def integrand(theta):
            s = a * np.sin(theta)
            kernel = np.log(abs(2.0 * np.sin(np.pi * (x - s) / wavelength)))
            return wavy.pressure(s, mean_pressure) * kernel * a * np.cos(theta)
        singular = [np.arcsin(x / a)] if abs(x) < a else []
        return -2.0 / (np.pi * CONTACT_MODULUS) * integrate(integrand, [-0.5 * np.pi, 0.5 * np.pi], singular)

    rigid_motion = displacement(0.0) + wavy.profile(0.0)
    for fraction in (-0.7, 0.3, 0.95):
        x = fraction * a
        assert displacement(x) + wavy.profile(x) == pytest.approx(rigid_motion, abs=1e-8 * wavy.amplitude)
    for x in np.linspace(a, wavelength - a, 9)[1:-1]:
        assert displacement(x) + wavy.profile(x) - rigid_motion > 0.0  # open gap


def test_westergaard_half_width_is_continuous(wavy):
    full = wavy.full_contact_pressure
    assert wavy.contact_half_width(full * (1.0 - 1e-12)) == pytest.approx(0.5 * wavy.wavelength, rel=1e-5)
    assert wavy.contact_half_width(2.0 * full) == 0.5 * wavy.wavelength
    x = np.linspace(0.0, 1.0, 11) * wavy.wavelength
    np.testing.assert_allclose(wavy.pressure(x, full * (1.0 - 1e-12)), wavy.pressure(x, full),
                               atol=1e-5 * full)
