"""Analytical solutions for cracks in an infinite elastic medium (plane strain).

Reference solutions of geoblock's contact verification (tests/verification/
contact.sh) and plots (postproc/plot_fracture.py). numpy only.

Conventions (geoblock's): tractions positive in tension, so a compressive
normal traction t_N is negative; the jump is u_plus - u_minus, g_N > 0 opens.
All functions take numpy arrays and SI units (m, Pa).

Sources
-------
* I. N. Sneddon, "The distribution of stress in the neighbourhood of a crack
  in an elastic solid", Proc. R. Soc. Lond. A 187 (1946) 229-260; the plane
  strain (Griffith) crack under uniform internal pressure p:
      g_N(x) = 4 (1 - nu^2) p / E * sqrt(b^2 - x^2),  |x| <= b.
* C. Phan, J. A. L. Napier, L. J. Gray, S. Song and G. H. Paulino (2003),
  frictional contact of a closed crack with the symmetric-Galerkin boundary
  element method, and A. Franceschini, N. Castelletto, J. A. White and
  H. A. Tchelepi, CMAME 368 (2020) 113161, section on the inclined fracture:
  a closed straight crack of half-length b at angle psi to a uniaxial
  compression sigma, Coulomb friction coefficient mu (no cohesion). With
  cot(psi) > mu the whole crack slips and
      t_N = -sigma sin^2(psi),   |t_T| = mu |t_N|,
      |g_T|(s) = 4 (1 - nu^2) / E * sigma sin(psi) (cos(psi) - mu sin(psi))
                 * sqrt(b^2 - s^2),
  the slip being the plane strain crack opening under the excess shear
  sigma sin(psi) (cos(psi) - mu sin(psi)).
"""
import numpy as np


def ellipse(x, b, width=None):
    """sqrt(b^2 - x^2) (0 beyond |x| = b); with width, its mean over
    [x - width/2, x + width/2], the quantity a P0 element of that width holds
    (exact integral: (x sqrt(b^2 - x^2) + b^2 asin(x / b)) / 2)."""
    x = np.asarray(x, dtype=float)
    if width is None:
        return np.sqrt(np.maximum(b * b - x * x, 0.0))

    def primitive(y):
        y = np.clip(y, -b, b)
        return 0.5 * (y * np.sqrt(np.maximum(b * b - y * y, 0.0)) + b * b * np.arcsin(y / b))
    return (primitive(x + 0.5 * width) - primitive(x - 0.5 * width)) / width


def sneddon_opening(x, b, p, young, poisson, width=None):
    """Opening g_N [m] at distance x [m] from the centre of a plane strain
    crack of half-length b under internal pressure p [Pa] (with width: its
    mean over an element of that width centred at x)."""
    return 4.0 * (1.0 - poisson**2) * p / young * ellipse(x, b, width)


def inclined_crack(s, b, sigma, psi_deg, friction_angle_deg, young, poisson, width=None):
    """Slip |g_T| [m], normal traction t_N [Pa] and tangential traction
    |t_T| [Pa] at distance s [m] from the centre of a closed crack of
    half-length b at psi degrees from a uniaxial compression sigma > 0 [Pa],
    friction angle in degrees (with width: the slip's mean over an element of
    that width centred at s). Raises ValueError if the crack would not slip."""
    s = np.asarray(s, dtype=float)
    psi = np.radians(psi_deg)
    mu = np.tan(np.radians(friction_angle_deg))
    excess = sigma * np.sin(psi) * (np.cos(psi) - mu * np.sin(psi))
    if excess <= 0.0:
        raise ValueError("the crack sticks: cot(psi) <= tan(friction angle)")
    slip = 4.0 * (1.0 - poisson**2) / young * excess * ellipse(s, b, width)
    tn = -sigma * np.sin(psi) ** 2 * np.ones_like(s)
    tt = mu * np.abs(tn)
    return slip, tn, tt


def relative_l2(num, ref, mask=None):
    """||num - ref|| / ||ref|| over mask (all entries by default)."""
    num = np.asarray(num, dtype=float)
    ref = np.asarray(ref, dtype=float)
    if mask is not None:
        num, ref = num[mask], ref[mask]
    return float(np.linalg.norm(num - ref) / np.linalg.norm(ref))


if __name__ == "__main__":
    import argparse
    argparse.ArgumentParser(description="Analytical fracture solutions (Sneddon opening, inclined crack); run "
                            "as a script it checks itself.").parse_args()
    # self-check: the slip equals the opening of a crack under the excess shear
    x = np.linspace(-1.0, 1.0, 11)
    slip, tn, tt = inclined_crack(x, 1.0, 1.0e7, 20.0, 30.0, 1.0e10, 0.25)
    excess = 1.0e7 * np.sin(np.radians(20)) * (np.cos(np.radians(20)) - np.tan(np.radians(30)) * np.sin(np.radians(20)))
    assert np.allclose(slip, sneddon_opening(x, 1.0, excess, 1.0e10, 0.25))
    assert abs(sneddon_opening(0.0, 1.0, 1.0e6, 1.0e10, 0.25) - 3.75e-4) < 1e-15
    # element means: a quarter-ellipse over [0, b] has mean pi b / 4; a fine
    # midpoint sum agrees; an element straddling the tip holds half its area
    assert abs(ellipse(0.5, 1.0, 1.0) - np.pi / 4) < 1e-14
    xs = 0.3 + (np.arange(20000) + 0.5) / 20000 * 0.2 - 0.1
    assert abs(ellipse(0.3, 1.0, 0.2) - ellipse(xs, 1.0).mean()) < 1e-9
    assert abs(ellipse(1.0, 1.0, 0.2) - ellipse(0.95, 1.0, 0.1) / 2) < 1e-14
    print("fracture_analytical: self-check passed")
