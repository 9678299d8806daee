"""Exact 2D reference in finite depth: a fixed-draft rectangle by matched eigenfunction
expansions (MEEM), numpy/scipy only.

Geometry: half-breadth b, draft d, water depth h > d, free surface y = 0, bottom y = -h,
gap s = h - d under the body. Time factor exp(+i omega t), nu = omega^2/g, potentials per unit
velocity of the body (sway: x, heave: y, roll: counter-clockwise about (0, y_roll), displacement
(-(y - y_roll), x)). With n the normal out of the body into the fluid and dphi_j/dn = n_j,

    A~_ij = a_ij - i b_ij / omega = -rho  int_body  phi_j n_i ds     (per metre, SI).

Exterior x > b (u = y + h in [0, h]):

    phi_1 = sum_{m=0}^{M} A_m Z_m(u) e^{-lambda_m (x - b)},
    Z_0 = cosh(k u)/cosh(k h),  nu = k tanh(k h),       lambda_0 = i k (outgoing),
    Z_m = cos(k_m u),           nu = -k_m tan(k_m h),   lambda_m = k_m  (m >= 1),

orthogonal on [0, h] with norms N_m = int_0^h Z_m^2 du; x < -b by parity (heave even, sway and
roll odd). Gap 0 < x < b, u in [0, s]:

    phi_2 = phi_p + sum_{n=0}^{N} B_n cos(n pi u/s) X_n(x),
    even: X_0 = 1, X_n = cosh(n pi x/s)/cosh(n pi b/s);  odd: X_0 = x/b, X_n = sinh/sinh,
    heave phi_p = (u^2 - x^2)/(2s)           (dphi/dy = 1 on the body's bottom u = s),
    roll  phi_p = x u^2/(2s) - x^3/(6s)      (dphi/dy = x there),   sway phi_p = 0.

Matching at x = b: the horizontal velocity, projected on Z_l over [0, h] (the wall u in [s, h]
prescribes dphi/dx = n_j there: sway 1, roll -(y - y_roll), heave 0),

    -lambda_l N_l A_l - sum_n B_n X_n'(b) L_nl = int_s^h v_wall Z_l du + int_0^s dphi_p/dx Z_l du,

and the potential, projected on cos(n pi u/s) over [0, s],

    sum_m A_m L_nm - eps_n s B_n = int_0^s phi_p(b, u) cos(n pi u/s) du,

with L_nm = int_0^s cos(n pi u/s) Z_m(u) du, eps_0 = 1, eps_n = 1/2. The gap truncation
follows the exterior's (N ~ M s/h, equal vertical resolution on both sides of x = b). The
corner (x = b, u = s) makes the velocity singular like r^(-1/3), so the series converge
algebraically (measured: like M^-2); docs/FINITE_DEPTH.md gives the measured digits.

Far field and energy: phi_j -> A_0 Z_0(u) e^{-ik|x|}, the wave elevation per unit velocity is
omega |A_0| / g, and the radiated power of both sides equals b_jj / 2:

    b_jj = 2 rho omega^2 c_g |A_0|^2 / g,   c_g = (omega / 2k)(1 + 2kh / sinh 2kh).

Haskind: the exciting force of a unit-amplitude wave has |X_j| = 2 rho omega c_g |A_0| (the
wave's elevation a = 1 m).
"""
import functools

import numpy as np
from scipy.linalg import lu_factor, lu_solve
from scipy.optimize import brentq

RHO = 1025.0
G = 9.81


def wavenumbers(nu, h, count):
    """(k, [k_1 .. k_count]): the propagating root of nu = k tanh kh and the evanescent roots of
    nu = -k_m tan k_m h, with k_m h in ((m - 1/2) pi, m pi)."""
    nh = nu * h
    x0 = brentq(lambda x: x * np.tanh(x) - nh, 1e-14, nh + 1.0 + np.sqrt(nh),
                xtol=1e-15, rtol=1e-15)
    roots = np.empty(count)
    for m in range(1, count + 1):
        lo = (m - 0.5) * np.pi
        hi = m * np.pi
        # x tan x + nu h rises from -inf at lo to nu h > 0 at hi.
        eps = 1e-14 * m
        roots[m - 1] = brentq(lambda x: x * np.tan(x) + nh, lo + eps, hi, xtol=1e-15, rtol=1e-15)
    return x0 / h, roots / h


def _sinc(z):
    z = np.asarray(z, dtype=complex)
    out = np.ones_like(z)
    big = np.abs(z) > 1e-8
    out[big] = np.sin(z[big]) / z[big]
    return out


@functools.lru_cache(maxsize=8)
def _legendre(n):
    return np.polynomial.legendre.leggauss(n)


def _gauss(a, c, n):
    x, w = _legendre(n)
    return 0.5 * (c - a) * x + 0.5 * (c + a), 0.5 * (c - a) * w


class _Basis:
    """Eigenfunctions of both regions for one frequency and truncation."""

    def __init__(self, d, h, omega, terms, gap_terms):
        self.h, self.s = h, h - d
        self.nu = omega**2 / G
        k, km = wavenumbers(self.nu, h, terms)
        self.k = k
        # kappa_m with Z_m = cos(kappa_m u)/scale_m; kappa_0 = -ik gives cosh(ku).
        self.kappa = np.concatenate([[-1j * k], km.astype(complex)])
        self.scale = np.concatenate([[np.cosh(k * h)], np.ones(terms)])
        self.lam = np.concatenate([[1j * k], km.astype(complex)])
        kh = self.kappa * h
        self.norm = 0.5 * h * (1.0 + _sinc(2.0 * kh)) / self.scale**2
        self.alpha = np.arange(gap_terms + 1) * np.pi / self.s
        a = self.alpha[:, None]
        kap = self.kappa[None, :]
        # L_nm = int_0^s cos(alpha_n u) cos(kappa_m u) du / scale_m
        self.L = 0.5 * self.s * (_sinc((a - kap) * self.s) + _sinc((a + kap) * self.s)) / self.scale
        self.eps = np.where(np.arange(gap_terms + 1) == 0, 1.0, 0.5)
        # Quadrature resolving the highest modes on the wall and in the gap.
        nq = int(terms + gap_terms) + 200
        self.u_wall, self.w_wall = _gauss(self.s, h, nq)
        self.u_gap, self.w_gap = _gauss(0.0, self.s, nq)
        self.Z_wall = self.Z(self.u_wall)
        self.Z_gap = self.Z(self.u_gap)
        self.cos_gap = np.cos(np.outer(self.u_gap, self.alpha))
        self._lu = {}

    def Z(self, u):
        return np.cos(np.outer(u, self.kappa)) / self.scale


def _gap_factor(alpha, b, x, even):
    """X_n(x) for n >= 1 (overflow-free) and their derivatives at x = b."""
    a = alpha[1:]
    if even:
        ratio = np.exp(a * (x - b)) * (1 + np.exp(-2 * a * x)) / (1 + np.exp(-2 * a * b))
        slope_b = a * np.tanh(a * b)
    else:
        ratio = np.exp(a * (x - b)) * (1 - np.exp(-2 * a * x)) / (1 - np.exp(-2 * a * b))
        slope_b = a / np.tanh(a * b)
    return ratio, slope_b


def _solve(basis, b, mode, y_roll):
    """Expansion coefficients (A, B) of the radiation potential of `mode`."""
    h, s = basis.h, basis.s
    even = mode == "heave"
    uw, ww = basis.u_wall, basis.w_wall
    ug, wg = basis.u_gap, basis.w_gap
    if mode == "heave":
        v_wall = np.zeros_like(uw)
        dpdx = np.full_like(ug, -b / s)
        p_b = (ug**2 - b**2) / (2 * s)
    elif mode == "sway":
        v_wall = np.ones_like(uw)
        dpdx = np.zeros_like(ug)
        p_b = np.zeros_like(ug)
    elif mode == "roll":
        v_wall = -(uw - h - y_roll)
        dpdx = (ug**2 - b**2) / (2 * s)
        p_b = b * ug**2 / (2 * s) - b**3 / (6 * s)
    else:
        raise ValueError(mode)
    M1, N1 = len(basis.kappa), len(basis.alpha)
    if even not in basis._lu:
        slope = np.empty(N1)
        slope[0] = 0.0 if even else 1.0 / b
        slope[1:] = _gap_factor(basis.alpha, b, b, even)[1]
        system = np.zeros((M1 + N1, M1 + N1), dtype=complex)
        # velocity, projected on Z_l
        system[:M1, :M1] = np.diag(-basis.lam * basis.norm)
        system[:M1, M1:] = -(basis.L * slope[:, None]).T
        # potential, projected on cos(alpha_n u)
        system[M1:, :M1] = basis.L
        system[M1:, M1:] = np.diag(-basis.eps * s)
        basis._lu[even] = lu_factor(system)
    rhs = np.zeros(M1 + N1, dtype=complex)
    rhs[:M1] = (v_wall * ww) @ basis.Z_wall + (dpdx * wg) @ basis.Z_gap
    rhs[M1:] = (p_b * wg) @ basis.cos_gap
    sol = lu_solve(basis._lu[even], rhs)
    return sol[:M1], sol[M1:]


def _forces(basis, b, mode, A, B, y_roll):
    """-rho int phi_j n_i ds for i in (sway, heave, roll): walls from the exterior expansion,
    the bottom from the gap expansion."""
    h, s = basis.h, basis.s
    even = mode == "heave"
    uw, ww = basis.u_wall, basis.w_wall
    phi_wall = basis.Z_wall @ A  # right wall; the left is +-phi_wall
    y = uw - h
    # right wall n = (1, 0): n_sway 1, n_roll -(y - y_roll); left wall n = (-1, 0).
    parity = 1.0 if even else -1.0
    sway = -RHO * (1 - parity) * np.sum(ww * phi_wall)
    roll = -RHO * (1 - parity) * np.sum(ww * phi_wall * -(y - y_roll))
    # bottom y = -d, n = (0, -1): n_heave -1, n_roll -x; phi_2(x, s) on x in [0, b].
    xq, wq = _gauss(0.0, b, 200)
    if mode == "heave":
        p = (s**2 - xq**2) / (2 * s)
    elif mode == "roll":
        p = xq * s / 2 - xq**3 / (6 * s)
    else:
        p = np.zeros_like(xq)
    a = basis.alpha[1:]
    cos_s = np.cos(basis.alpha * s)
    sech = 2 * np.exp(-a * b) / (1 + np.exp(-2 * a * b))  # 1/cosh(ab) without overflow
    if even:
        # int_0^b X_n dx, int_0^b x X_n dx
        i0 = np.concatenate([[b], np.tanh(a * b) / a])
        i1 = np.concatenate([[b**2 / 2], b * np.tanh(a * b) / a - (1 - sech) / a**2])
    else:
        i0 = np.concatenate([[b / 2], (1 - sech) / (a * np.tanh(a * b))])
        i1 = np.concatenate([[b**2 / 3], b / (a * np.tanh(a * b)) - 1 / a**2])
    int_phi = np.sum(wq * p) + np.sum(B * cos_s * i0)  # int_0^b phi_2(x, s) dx
    int_xphi = np.sum(wq * xq * p) + np.sum(B * cos_s * i1)  # int_0^b x phi_2(x, s) dx
    # over [-b, b]: phi even -> 2 int phi, 0 for x phi; odd -> 0, 2 int x phi
    heave = -RHO * (-1.0) * (2 * int_phi if even else 0.0)
    roll += -RHO * (-1.0) * (2 * int_xphi if not even else 0.0)
    return {"sway": sway, "heave": heave, "roll": roll}


def coefficients(b, d, h, omega, terms=200, gap_terms=None, y_roll=0.0,
                 modes=("sway", "heave", "roll")):
    """Added mass and damping per metre of the rectangle (SI, rho = 1025, g = 9.81).

    Returns {(i, j): (a_ij, b_ij)} for i, j in `modes` (pairs of opposite parity are zero and
    left out), plus "far" -> {j: A_0} (the outgoing wave's potential amplitude per unit velocity
    at y = 0) and "k" (propagating wavenumber). `terms` evanescent exterior modes, `gap_terms`
    gap modes (default: terms s/h, at least 8)."""
    if not 0 < d < h:
        raise ValueError("need 0 < d < h")
    s = h - d
    if gap_terms is None:
        gap_terms = max(8, int(round(terms * s / h)))
    basis = _Basis(d, h, omega, terms, gap_terms)
    out = {"far": {}, "k": basis.k}
    for j in modes:
        A, B = _solve(basis, b, j, y_roll)
        out["far"][j] = A[0]
        forces = _forces(basis, b, j, A, B, y_roll)
        for i in modes:
            if (i == "heave") != (j == "heave"):
                continue
            c = forces[i]
            out[(i, j)] = (c.real, -omega * c.imag)
    return out


def group_velocity(omega, k, h):
    return omega / (2 * k) * (1 + 2 * k * h / np.sinh(2 * k * h))


def energy_damping(omega, k, h, far):
    """b_jj from the outgoing wave: both sides carry rho omega^2 c_g |A_0|^2 / (2g)."""
    return 2 * RHO * omega**2 * group_velocity(omega, k, h) * abs(far) ** 2 / G


def haskind_force(omega, k, h, far):
    """|X_j| per metre for a wave of unit amplitude (1 m), from Haskind at infinity."""
    return 2 * RHO * omega * group_velocity(omega, k, h) * abs(far)
