"""Linear water waves for the example scripts: the dispersion relation and the group velocity
in water of depth h (None or inf: deep water), omega in rad/s, g = 9.81 m/s^2.

    omega^2 = g k tanh(k h),    c_g = (omega / 2k) (1 + 2kh / sinh 2kh)
"""
import math

import numpy as np

G = 9.81


def deep(depth):
    return depth is None or math.isinf(depth)


def wavenumber(omega, depth=None):
    """The root k of omega^2 = g k tanh(k h) (omega^2 / g in deep water), by Newton's method
    from below the root (tanh(kh) < 1 and tanh(kh) < kh); omega a number or an array."""
    nu = np.asarray(omega, float) ** 2 / G
    if deep(depth):
        return nu
    k = np.maximum(nu, np.sqrt(nu / depth))
    for _ in range(60):
        t = np.tanh(k * depth)
        k = k - (k * t - nu) / (t + k * depth * (1 - t * t))
    return k


def group_velocity(omega, depth=None):
    k = wavenumber(omega, depth)
    if deep(depth):
        return np.asarray(omega, float) / (2 * k)
    return np.asarray(omega, float) / (2 * k) * (1 + 2 * k * depth / np.sinh(2 * k * depth))
