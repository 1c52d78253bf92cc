"""The surface flexibility of a horizontally layered viscoelastic half-space
in the frequency-wavenumber domain: the direct stiffness method of
E. Kausel and J. M. Roesset, "Stiffness matrices for layered soils",
Bull. Seismol. Soc. Am. 71(6) (1981) 1743-1761, written here from the
layer's wave solutions rather than from their closed-form matrices.

Plane-strain P-SV fields (the vertical-vertical term of the axisymmetric
problem is the same function of the wavenumber k, Kausel & Roesset 1981),
x along the surface, z DOWN, time factor exp(i w t), horizontal factor
exp(-i k x). In a layer the displacement (u_x, u_z) is a sum of four
waves, each (a + b z') exp(s z') with z' measured from the interface the
wave is referenced to (down-going waves from the layer's top, up-going
from its bottom, so that every exponential is at most 1 and the matrices
stay well conditioned at large k h):

    P down  a = (-ik, -nu_P), s = -nu_P      P up  a = (-ik, nu_P), s = nu_P
    S down  a = (nu_S, -ik),  s = -nu_S      S up  a = (-nu_S, -ik), s = nu_S

nu = sqrt(k^2 - w^2/c^2), Re nu >= 0. At w = 0 the P and S waves merge and
the static solutions replace them: grad(phi) and the Papkovich-Neuber
solution (3 - 4 nu_Poisson) phi e_z - z' grad(phi), phi = exp(s z' - ikx),
s = -+k (there b != 0). The layer's stiffness K = S D^-1 maps the
displacements at its top and bottom to the external tractions there; the
half-space has the down-going waves only. The layers are condensed onto
the surface from the bottom up; the flexibility is the vertical
displacement under a unit vertical stress (both positive down),
G(k, w) = [Z_0^-1]_zz. Homogeneous static check: G = (1 - nu)/(mu k).

Material damping is hysteretic from about 1 Hz up: mu* = mu (1 + 2 i xi s),
lambda* the same, s = x / sqrt(1 + x^2), x = Re w / (2 pi f_l), f_l =
LOSS_ONSET = 0.25 Hz (s = 0.97 at 1 Hz, 0.995 at 2.5 Hz). A loss factor
constant down to w = 0 (s = sgn w) has no static limit in the time domain:
its response to a held force creeps like ln t, by about 4 xi / pi of the
static value per e-fold of time. The static flexibility (w = 0) is the
elastic one.

For a comparison with the FE soil, whose material is damped the Rayleigh
way (C = a0 M + a1 K, the layer's xi matched at the two frequencies of its
damping band: fe_soil/params.py), a layer given as `RayleighLayer` takes
that law instead. In the frequency domain the FE soil's equation of motion
(-w^2 + i w a0) rho u + (1 + i w a1 / (1 + i w tau)) K u = f (tau the time
constant of the filter on the velocity above its damping cutoff, 0 without
one) is that of an elastic medium with the complex density
rho (1 - i a0 / w) and the complex moduli mu s, lambda s with
s = 1 + i w a1 / (1 + i w tau), the traction on the surface unchanged:
exactly the FE soil's material, causal by itself (no onset).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Tuple

import numpy as np

from fe_soil.params import Layer, rayleigh_coefficients


LOSS_ONSET = 0.25  # Hz: below it the loss factor fades (see the module's text)


@dataclass
class RayleighLayer(Layer):
    """A layer damped as the FE soil damps it: `damping` matched at the two
    frequencies of `rayleigh_band` (Hz) by C = a0 M + a1 K, the stiffness
    part filtered above `damping_cutoff` (Hz; 0: not filtered)."""

    rayleigh_band: Tuple[float, float] = (5.0, 50.0)
    damping_cutoff: float = 0.0


def rayleigh_layers(layers, band, cutoff=0.0):
    """The layers with the FE soil's damping law fitted over band (Hz),
    filtered above cutoff (Hz; 0: Rayleigh damping)."""
    return [RayleighLayer(l.thickness, l.density, l.shear_speed, l.poisson, l.damping,
                          (float(band[0]), float(band[1])), float(cutoff)) for l in layers]


def moduli(layer, w):
    """(mu*, lambda*, rho*) of a layer at the complex circular frequency w:
    hysteretic, or the FE soil's Rayleigh law for a RayleighLayer (its
    density complex; at w = 0, where only the moduli enter, the elastic
    ones)."""
    mu = layer.density * layer.shear_speed**2
    nu = layer.poisson
    lam = 2.0 * mu * nu / (1.0 - 2.0 * nu)
    band = getattr(layer, "rayleigh_band", None)
    if band is not None:
        if w == 0:
            return mu + 0j, lam + 0j, layer.density
        cutoff = layer.damping_cutoff
        a0, a1 = rayleigh_coefficients(layer.damping, *band, cutoff)
        tau = 1.0 / (2.0 * np.pi * cutoff) if cutoff > 0.0 else 0.0
        stiff = 1.0 + 1j * w * a1 / (1.0 + 1j * w * tau)
        return mu * stiff, lam * stiff, layer.density * (1.0 - 1j * a0 / w)
    x = np.real(w) / (2.0 * np.pi * LOSS_ONSET)
    loss = 1.0 + 2.0j * layer.damping * x / np.sqrt(1.0 + x * x)
    return mu * loss, lam * loss, layer.density


def _root(x):
    """sqrt with Re >= 0 (and Im >= 0 on the imaginary axis)."""
    r = np.sqrt(x.astype(complex))
    return np.where((r.real < 0) | ((r.real == 0) & (r.imag < 0)), -r, r)


def _waves(layer, k, w, half_space):
    """The basis of a layer's waves: lists (a, b, s, at_top) per wave,
    a and b arrays (n, 2), s an array (n,)."""
    n = len(k)
    ik = 1j * k
    zero = np.zeros(n, complex)
    mu, lam, rho = moduli(layer, w)
    if w == 0:
        poisson = layer.poisson
        out = []
        for sign, top in ((-1.0, True), (1.0, False)):
            s = sign * k.astype(complex)
            out.append((np.stack([-ik, s], 1), np.zeros((n, 2), complex), s, top))
            out.append((np.stack([zero, zero + 3.0 - 4.0 * poisson], 1),
                        np.stack([ik, -s], 1), s, top))
            if half_space:
                break
        return out, mu, lam
    nu_p = _root(k**2 - w**2 * rho / (lam + 2.0 * mu))
    nu_s = _root(k**2 - w**2 * rho / mu)
    b0 = np.zeros((n, 2), complex)
    out = [(np.stack([-ik, -nu_p], 1), b0, -nu_p, True),
           (np.stack([nu_s, -ik], 1), b0, -nu_s, True)]
    if not half_space:
        out += [(np.stack([-ik, nu_p], 1), b0, nu_p, False),
                (np.stack([-nu_s, -ik], 1), b0, nu_s, False)]
    return out, mu, lam


def _at(wave, z, k, mu, lam):
    """Displacement (n, 2) and traction on a face of downward normal,
    (sigma_xz, sigma_zz) (n, 2), of one wave at z' = z (scalar)."""
    a, b, s, _ = wave
    e = np.exp(s * z) if np.isscalar(z) and z != 0 else np.ones_like(s)
    u = (a + b * z) * e[:, None]
    du = (b + s[:, None] * (a + b * z)) * e[:, None]
    ik = 1j * k
    sxz = mu * (du[:, 0] - ik * u[:, 1])
    szz = lam * (-ik * u[:, 0] + du[:, 1]) + 2.0 * mu * du[:, 1]
    return u, np.stack([sxz, szz], 1)


def layer_stiffness(layer, k, w, half_space=False):
    """The layer's stiffness, (n, 4, 4) (top x, top z, bottom x, bottom z),
    or the half-space's (n, 2, 2)."""
    waves, mu, lam = _waves(layer, k, w, half_space)
    h = 0.0 if half_space else layer.thickness
    cols_d, cols_s = [], []
    for wave in waves:
        z_top, z_bot = (0.0, h) if wave[3] else (-h, 0.0)
        u_t, t_t = _at(wave, z_top, k, mu, lam)
        if half_space:
            cols_d.append(u_t)
            cols_s.append(-t_t)
            continue
        u_b, t_b = _at(wave, z_bot, k, mu, lam)
        cols_d.append(np.concatenate([u_t, u_b], 1))
        cols_s.append(np.concatenate([-t_t, t_b], 1))
    d = np.stack(cols_d, 2)
    s = np.stack(cols_s, 2)
    # K = S D^-1, i.e. D^T K^T = S^T.
    return np.swapaxes(np.linalg.solve(np.swapaxes(d, 1, 2), np.swapaxes(s, 1, 2)), 1, 2)


def _inv2(m):
    det = m[:, 0, 0] * m[:, 1, 1] - m[:, 0, 1] * m[:, 1, 0]
    out = np.empty_like(m)
    out[:, 0, 0], out[:, 1, 1] = m[:, 1, 1] / det, m[:, 0, 0] / det
    out[:, 0, 1], out[:, 1, 0] = -m[:, 0, 1] / det, -m[:, 1, 0] / det
    return out


def surface_flexibility(layers, k, w):
    """G(k, w): vertical surface displacement per unit vertical surface
    stress (2D Fourier transforms), for wavenumbers k (array, >= 0; k > 0 at
    w = 0) and one complex circular frequency w (Im w <= 0)."""
    k = np.asarray(k, dtype=float)
    z = layer_stiffness(layers[-1], k, w, half_space=True)
    for layer in reversed(layers[:-1]):
        kl = layer_stiffness(layer, k, w)
        k11, k12, k21, k22 = kl[:, :2, :2], kl[:, :2, 2:], kl[:, 2:, :2], kl[:, 2:, 2:]
        z = k11 - k12 @ _inv2(k22 + z) @ k21
    return _inv2(z)[:, 1, 1]


def top_static(layers, w=0.0):
    """(1 - nu)/mu* of the top layer: G of its half-space at w = 0 is this
    over k (the large-k asymptote of every layered G)."""
    mu, _, _ = moduli(layers[0], w)
    return (1.0 - layers[0].poisson) / mu
