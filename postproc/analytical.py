"""Analytical solutions of Terzaghi's, Mandel's and Cryer's consolidation problems,
and of a pressure-controlled source in a column (SourceColumn).

Reference solutions for geoblock's verification tests and plots. Needs only
numpy (Debian python3-numpy); the example plot also needs matplotlib
(python3-matplotlib). No scipy: the roots of Mandel's and Cryer's equations
are found by bisections written here.

Conventions (the same as geoblock's Biot model)
-----------------------------------------------
* SI units throughout: m, s, Pa, N; permeability k in m^2, viscosity mu in Pa s.
* Stresses are positive in tension (Biot, Coussy); the pore pressure p is the
  excess over the initial (zero) pressure. Loads are given as positive numbers
  meaning compression (sigma0 in Terzaghi, F in Mandel).
* Poroelastic model (Coussy 2004):
      sigma = 2 G eps + lambda tr(eps) I - b p I,
      (1/M) dp/dt + b d tr(eps)/dt + div q = 0,   q = -(k/mu) grad p.

Sources actually used
---------------------
* O. Coussy, "Poromechanics", Wiley, 2004: the parameters b (Biot coefficient),
  M (Biot modulus), K_u = K + b^2 M, Skempton B = b M / K_u.
* E. Detournay and A. H.-D. Cheng, "Fundamentals of poroelasticity", in
  Comprehensive Rock Engineering vol. 2, Pergamon, 1993: the identities
  B = 3 (nu_u - nu) / (b (1 - 2 nu)(1 + nu_u)) and
  c = k/mu (K_u - K)(K + 4G/3) / (b^2 (K_u + 4G/3)) (generalized consolidation
  coefficient), which the self-check verifies numerically.
* A. Verruijt, "Theory and Problems of Poroelasticity" (Delft, 2013/2016
  lecture book), chapter on Terzaghi's problem: the Fourier series of the
  pressure and the degree of consolidation.
* H. S. Carslaw and J. C. Jaeger, "Conduction of Heat in Solids", 2nd ed.,
  Oxford, 1959 (linear flow in a slab): the small-time (method of images)
  form of the slab solution in erfc terms, used here for c_v t / H^2 < 0.25.
* J. Mandel, "Consolidation des sols (etude mathematique)", Geotechnique 3
  (1953) 287-299: the problem.
* A. H.-D. Cheng and E. Detournay, "A direct boundary element method for plane
  strain poroelasticity", Int. J. Numer. Anal. Methods Geomech. 12 (1988)
  551-572, and Y. Abousleiman, A. H.-D. Cheng, L. Cui, E. Detournay and
  J.-C. Roegiers, "Mandel's problem revisited", Geotechnique 46 (1996) 187-195:
  Mandel's solution (pressure, displacements, vertical stress) and the
  consolidation coefficient c = 2 k/mu B^2 G (1-nu)(1+nu_u)^2 /
  (9 (1-nu_u)(nu_u-nu)). Their convention for the load is used: a total force
  2F per unit out-of-plane length on each plate.
* C. W. Cryer, "A comparison of the three-dimensional consolidation theories
  of Biot and Terzaghi", Q. J. Mech. Appl. Math. 16 (1963) 401-412: the
  problem (a sphere loaded by a uniform radial stress, drained on its
  surface) and the rise of the centre pressure above its undrained value;
  Verruijt (above), chapter on Cryer's problem, gives the characteristic
  equation for incompressible constituents,
  tan xi = xi / (1 - (1-nu) xi^2 / (2 (1-2nu))). The Cryer class derives the
  series for compressible constituents by Laplace transform (its docstring);
  for M = inf and b = 1 its equation is Verruijt's.
The self-check (test_analytical.py) verifies every series formula against the
governing equations themselves (equilibrium, constitutive law, mass balance,
boundary and initial conditions), so a misprint in a source would be caught.

Accuracy
--------
Every series is truncated with a rigorous bound on the discarded tail: the
absolute truncation error is below tol times the natural scale of the result
(p0 for pressures, the undrained or drained scale given in each docstring for
displacements and stresses). t = 0 returns the undrained (t = 0+) state in
closed form; at a drained boundary the pressure returned at t = 0 is 0 (the
boundary condition, which holds for every t > 0).
"""
import math
from dataclasses import dataclass

import numpy as np

__all__ = [
    "PoroParams", "Terzaghi", "Mandel", "mandel_roots",
    "terzaghi_pressure", "terzaghi_displacement", "terzaghi_settlement",
    "mandel_pressure", "mandel_displacement_x", "mandel_displacement_y",
    "mandel_stress_yy", "Cryer", "cryer_roots", "plot_mandel_example",
]

_erfc = np.frompyfunc(math.erfc, 1, 1)


def _erfc_v(x):
    """Vectorized erfc (math.erfc elementwise; no scipy)."""
    return np.asarray(_erfc(np.asarray(x, dtype=float)), dtype=float)


def _ierfc_v(x):
    """First integral of erfc: ierfc(x) = int_x^inf erfc(s) ds
    = exp(-x^2)/sqrt(pi) - x erfc(x)."""
    x = np.asarray(x, dtype=float)
    return np.exp(-x * x) / math.sqrt(math.pi) - x * _erfc_v(x)


# --------------------------------------------------------------------------
# Parameters
# --------------------------------------------------------------------------

@dataclass(frozen=True)
class PoroParams:
    """Isotropic linear poroelastic material from geoblock's drained inputs.

    Inputs (the deck's &material names in brackets):
      E  [young]         drained Young's modulus, Pa (> 0)
      nu [poisson]       drained Poisson ratio, -1 < nu < 1/2
      b  [biot]          Biot coefficient, 0 <= b <= 1
      M  [biot_modulus]  Biot modulus, Pa (> 0; float('inf') for incompressible
                         fluid and grains)
      k  [permeability]  intrinsic permeability, m^2 (> 0)
      mu [viscosity]     fluid dynamic viscosity, Pa s (> 0)

    Derived properties (Coussy 2004; Detournay & Cheng 1993):
      K_dr = E / (3 (1 - 2 nu))                drained bulk modulus, Pa
      G    = E / (2 (1 + nu))                  shear modulus, Pa
      lam  = K_dr - 2G/3                       Lame's first parameter, Pa
      K_u  = K_dr + b^2 M                      undrained bulk modulus, Pa
      nu_u = (3 K_u - 2G) / (2 (3 K_u + G))    undrained Poisson ratio
      B    = b M / K_u                         Skempton coefficient
      K_v  = K_dr + 4G/3 = lam + 2G            drained constrained (oedometric)
                                               modulus, Pa
      K_vu = K_v + b^2 M                       undrained constrained modulus, Pa
      mobility = k / mu                        m^2 / (Pa s)
      S_v  = 1/M + b^2 / K_v                   storage coefficient at zero
                                               lateral strain, 1/Pa
      c_v  = (k/mu) / S_v = (k/mu) M K_v / (K_v + b^2 M)
                                               consolidation coefficient, m^2/s
      c_mandel = 2 (k/mu) B^2 G (1-nu)(1+nu_u)^2 / (9 (1-nu_u)(nu_u-nu))
                                               Mandel's coefficient (Cheng &
                                               Detournay 1988), m^2/s
    Dimensions: (k/mu) [m^2/(Pa s)] times a modulus [Pa] gives m^2/s.

    c_mandel equals c_v identically: with K_v = 2G(1-nu)/(1-2nu),
    K_vu = 2G(1-nu_u)/(1-2nu_u), b^2 M = K_u - K_dr and B as above, both reduce
    to (k/mu) 2G (1-nu)(nu_u-nu) / (b^2 (1-2nu)^2 (1-nu_u)); it is the
    generalized consolidation coefficient of Detournay & Cheng (1993). (In
    Mandel's problem the lateral stress vanishes and the out-of-plane strain
    is zero, so the pressure diffuses with the same storage 1/M + b^2/K_v as in
    the oedometer.) Both are kept so that the tests can compare them.

    All formulas are written with 1/M so that M = inf (incompressible
    constituents: K_u = inf, nu_u = 1/2, B = 1/b) works.
    """
    E: float
    nu: float
    b: float
    M: float
    k: float
    mu: float

    def __post_init__(self):
        checks = [
            ("E", self.E > 0 and math.isfinite(self.E), "E > 0"),
            ("nu", -1.0 < self.nu < 0.5, "-1 < nu < 0.5"),
            ("b", 0.0 <= self.b <= 1.0, "0 <= b <= 1"),
            ("M", self.M > 0, "M > 0 (inf allowed)"),
            ("k", self.k > 0 and math.isfinite(self.k), "k > 0"),
            ("mu", self.mu > 0 and math.isfinite(self.mu), "mu > 0"),
        ]
        for name, ok, rule in checks:
            if not ok:
                raise ValueError(f"PoroParams: {name} = {getattr(self, name)!r} "
                                 f"is out of range ({rule})")

    @classmethod
    def from_namelist(cls, material):
        """Build from a dict with the deck's &material names: young, poisson,
        biot, biot_modulus, permeability, viscosity (e.g. a &material of
        geoblock_h5.read_parameters); no biot_modulus (1/M = 0) is M = inf."""
        return cls(E=float(material["young"]), nu=float(material["poisson"]),
                   b=float(material["biot"]), M=float(material.get("biot_modulus", math.inf)),
                   k=float(material["permeability"]),
                   mu=float(material["viscosity"]))

    @property
    def inv_M(self):
        """1/M, 1/Pa (0 for M = inf)."""
        return 0.0 if math.isinf(self.M) else 1.0 / self.M

    @property
    def K_dr(self):
        return self.E / (3.0 * (1.0 - 2.0 * self.nu))

    @property
    def G(self):
        return self.E / (2.0 * (1.0 + self.nu))

    @property
    def lam(self):
        return self.K_dr - 2.0 * self.G / 3.0

    @property
    def K_u(self):
        return math.inf if math.isinf(self.M) else self.K_dr + self.b ** 2 * self.M

    @property
    def _inv_K_u(self):
        # 1/K_u = (1/M) / (K_dr/M + b^2), finite for M = inf
        den = self.K_dr * self.inv_M + self.b ** 2
        return self.inv_M / den if den > 0 else 1.0 / self.K_dr

    @property
    def nu_u(self):
        g = self.G * self._inv_K_u           # G / K_u
        return (3.0 - 2.0 * g) / (2.0 * (3.0 + g))

    @property
    def B(self):
        den = self.K_dr * self.inv_M + self.b ** 2   # K_u / M
        return self.b / den if den > 0 else 0.0

    @property
    def K_v(self):
        return self.K_dr + 4.0 * self.G / 3.0

    @property
    def K_vu(self):
        return math.inf if math.isinf(self.M) else self.K_v + self.b ** 2 * self.M

    @property
    def mobility(self):
        return self.k / self.mu

    @property
    def S_v(self):
        return self.inv_M + self.b ** 2 / self.K_v

    @property
    def c_v(self):
        return self.mobility / self.S_v

    @property
    def c_mandel(self):
        nu, nu_u, B = self.nu, self.nu_u, self.B
        if not nu_u > nu:
            raise ValueError("c_mandel needs nu_u > nu, i.e. b > 0")
        return (2.0 * self.mobility * B ** 2 * self.G * (1.0 - nu) * (1.0 + nu_u) ** 2
                / (9.0 * (1.0 - nu_u) * (nu_u - nu)))

    def summary(self):
        """Inputs and derived values as a dict (for logs and plot titles)."""
        names = ["E", "nu", "b", "M", "k", "mu", "K_dr", "G", "lam", "K_u", "nu_u",
                 "B", "K_v", "K_vu", "mobility", "S_v", "c_v"]
        out = {n: getattr(self, n) for n in names}
        if self.b > 0:
            out["c_mandel"] = self.c_mandel
        return out


# --------------------------------------------------------------------------
# Terzaghi
# --------------------------------------------------------------------------

_TERZAGHI_T_SWITCH = 0.25   # erfc (image) series below, Fourier series above


def _terzaghi_fourier_nterms(T, tol):
    """Terms m = 0..N-1 of the Fourier series so that the tail is < tol at
    time factor T > 0. With lam_m = (2m+1) pi/2 the term bound is
    (2/lam_m) exp(-lam_m^2 T), and lam_j^2 >= lam_m^2 + 2 (j-m) pi lam_m gives
    tail(m) <= (2/lam_m) exp(-lam_m^2 T) / (1 - exp(-2 pi lam_m T))."""
    m = 0
    while True:
        lam = (2 * m + 1) * math.pi / 2
        tail = (2.0 / lam) * math.exp(-lam * lam * T) / -math.expm1(-2 * math.pi * lam * T)
        if tail < tol:
            return max(m, 1)
        m += 1


def _terzaghi_image_nterms(T, tol):
    """Terms n = 0..N-1 of the erfc series so that the tail is < tol at
    0 < T <= _TERZAGHI_T_SWITCH. Term n is bounded by 2 erfc(n/sqrt(T)) and
    erfc(x + d) <= exp(-2xd - d^2) erfc(x), so
    tail(n) <= 2 erfc(n/sqrt(T)) / (1 - exp(-(2n+1)/T)) for n >= 1 (the
    displacement terms 2 sqrt(T) ierfc(.) obey the same bound for T <= 1/2)."""
    n = 1
    s = math.sqrt(T)
    while True:
        tail = 2.0 * math.erfc(n / s) / -math.expm1(-(2 * n + 1) / T)
        if tail < tol:
            return n
        n += 1


def _terzaghi_normalized(zeta, T, tol):
    """P = p/p0 and I = int_0^zeta P dzeta' on flat arrays zeta in [0, 1],
    T >= 0 (zeta = z/H, T = c_v t / H^2)."""
    P = np.empty_like(zeta)
    I = np.empty_like(zeta)
    zero = T == 0.0
    P[zero] = np.where(zeta[zero] < 1.0, 1.0, 0.0)
    I[zero] = zeta[zero]

    big = T >= _TERZAGHI_T_SWITCH
    if np.any(big):
        z, t = zeta[big], T[big]
        N = _terzaghi_fourier_nterms(float(t.min()), tol)
        ps = np.zeros_like(z)
        its = np.zeros_like(z)
        for m in range(N):
            lam = (2 * m + 1) * math.pi / 2
            e = np.exp(-lam * lam * t) * (2.0 * (-1) ** m / lam)
            ps += e * np.cos(lam * z)
            its += e * np.sin(lam * z) / lam
        P[big], I[big] = ps, its

    small = (~zero) & (~big)
    if np.any(small):
        z, t = zeta[small], T[small]
        N = _terzaghi_image_nterms(float(t.max()), tol)
        s2 = 2.0 * np.sqrt(t)
        phi = np.zeros_like(z)
        iphi = np.zeros_like(z)
        for n in range(N):
            sign = (-1) ** n
            lo = (2 * n + 1 - z) / s2
            hi = (2 * n + 1 + z) / s2
            phi += sign * (_erfc_v(lo) + _erfc_v(hi))
            iphi += sign * s2 * (_ierfc_v(lo) - _ierfc_v(hi))
        P[small] = 1.0 - phi
        I[small] = z - iphi
    return P, I


class _Consolidation:
    """What the series solutions share: the time factor T = c t / L^2 (c:
    self.c, L: self._length), the checked broadcast of points and times, and
    (Mandel, Cryer) the cached roots of the characteristic equation
    (self._find_roots(n), into self._roots)."""

    def time_factor(self, t):
        """T = c t / L^2 (dimensionless; L: H, a or R)."""
        return self.c * np.asarray(t, dtype=float) / self._length ** 2

    def roots(self, n):
        """First n roots of the characteristic equation (cached)."""
        if n > self._roots.size:
            self._roots = self._find_roots(max(n, 2 * self._roots.size))
        return self._roots[:n]

    def _points(self, x, t, scale, lo, where):
        """x / scale (flat, clipped to [lo, 1]), T (flat) and the shape x and
        t broadcast to; ValueError when x / scale leaves [lo, 1] (where: the
        interval in words) or t is negative or not finite."""
        x, t = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(t, dtype=float))
        shape = x.shape
        xi = x.ravel() / scale
        T = self.time_factor(t.ravel())
        name = type(self).__name__
        if np.any(xi < lo - 1e-12) or np.any(xi > 1 + 1e-12):
            raise ValueError(f"{name}: {where}")
        if np.any(T < 0) or not np.all(np.isfinite(T)):
            raise ValueError(f"{name}: t must be finite and >= 0")
        return np.clip(xi, lo, 1.0), T, shape


class Terzaghi(_Consolidation):
    """Terzaghi's one-dimensional consolidation (Biot's coupled form).

    Geometry and conventions: a column 0 <= z <= H (z upward, m); the base z = 0
    is fixed (u_z = 0) and impermeable (dp/dz = 0); the top z = H is drained
    (p = 0) and carries a compressive load sigma0 > 0 (Pa) applied at t = 0 and
    held constant (total sigma_zz = -sigma0 everywhere for t > 0); no lateral
    strain. u_z is positive upward, so the top moves by u_z(H, t) < 0; the
    settlement s(t) = -u_z(H, t) > 0.

    Initial (undrained, t = 0+) pressure, from zero fluid-content change
    (1/M) p + b eps_zz = 0 with eps_zz = (b p - sigma0)/K_v:
        p0 = b M sigma0 / (K_v + b^2 M)     [Pa]
    Consolidation equation (Verruijt; Coussy):
        dp/dt = c_v d2p/dz2,  c_v = (k/mu) M K_v / (K_v + b^2 M)   [m^2/s]
    Pressure, with zeta = z/H, T = c_v t / H^2 and lam_m = (2m+1) pi / 2
    (Verruijt, Terzaghi's problem):
        p = p0 sum_{m>=0} (4/pi) (-1)^m / (2m+1) cos(lam_m zeta) exp(-lam_m^2 T)
    For T < 0.25 the equivalent image series (Carslaw & Jaeger, slab)
        p = p0 [1 - sum_{n>=0} (-1)^n (erfc((2n+1-zeta)/(2 sqrt T))
                                       + erfc((2n+1+zeta)/(2 sqrt T)))]
    is used (few terms where the Fourier series needs many).
    Displacement (base fixed), from eps_zz = (b p - sigma0)/K_v:
        u_z(z, t) = (H/K_v) [b p0 I(zeta, T) - sigma0 zeta],
        I = int_0^zeta p/p0 = sum 2 (-1)^m / lam_m^2 sin(lam_m zeta) exp(-lam_m^2 T)
    Settlement: s(t) = -u_z(H, t), from s(0+) = sigma0 H / K_vu (undrained) to
    s(inf) = sigma0 H / K_v (drained); degree of consolidation
        U(T) = (s - s0)/(s_inf - s0) = 1 - sum 8/((2m+1)^2 pi^2) exp(-lam_m^2 T)
    (U ~ 2 sqrt(T/pi) at small T).

    Accuracy: absolute truncation error < tol * p0 for p, < tol * sigma0 H / K_v
    for displacements.
    """

    def __init__(self, params, H, sigma0):
        if not H > 0:
            raise ValueError(f"Terzaghi: column height H = {H!r} must be > 0")
        self.params = params
        self.H = float(H)
        self._length = self.H
        self.sigma0 = float(sigma0)

    @property
    def p0(self):
        """Undrained initial pressure b M sigma0 / (K_v + b^2 M), Pa."""
        p = self.params
        return p.b * self.sigma0 / (p.K_v * p.inv_M + p.b ** 2) if p.b > 0 else 0.0

    @property
    def c_v(self):
        return self.params.c_v

    @property
    def c(self):
        """Consolidation coefficient c_v, m^2/s."""
        return self.c_v

    def _prepare(self, z, t):
        return self._points(z, t, self.H, 0.0, "z must lie in [0, H]")

    def pressure(self, z, t, tol=1e-12):
        """Excess pore pressure p(z, t), Pa; z in m (0 base, H top), t in s;
        z and t broadcast against each other."""
        zeta, T, shape = self._prepare(z, t)
        P, _ = _terzaghi_normalized(zeta, T, tol)
        return (self.p0 * P).reshape(shape)

    def displacement(self, z, t, tol=1e-12):
        """Vertical displacement u_z(z, t), m, positive upward (base fixed)."""
        zeta, T, shape = self._prepare(z, t)
        _, I = _terzaghi_normalized(zeta, T, tol)
        p = self.params
        u = (self.H / p.K_v) * (p.b * self.p0 * I - self.sigma0 * zeta)
        return u.reshape(shape)

    def settlement(self, t, tol=1e-12):
        """Settlement of the top s(t) = -u_z(H, t), m (positive downward)."""
        return -self.displacement(self.H, t, tol)

    def degree_of_consolidation(self, t, tol=1e-12):
        """U(t) = (s(t) - s(0)) / (s(inf) - s(0)), from 0 to 1."""
        zeta, T, shape = self._prepare(self.H, t)
        _, I = _terzaghi_normalized(zeta, T, tol)
        return (1.0 - I).reshape(shape)


def terzaghi_pressure(params, H, sigma0, z, t, tol=1e-12):
    """Terzaghi(params, H, sigma0).pressure(z, t): pore pressure, Pa."""
    return Terzaghi(params, H, sigma0).pressure(z, t, tol)


def terzaghi_displacement(params, H, sigma0, z, t, tol=1e-12):
    """Terzaghi(params, H, sigma0).displacement(z, t): u_z, m, up positive."""
    return Terzaghi(params, H, sigma0).displacement(z, t, tol)


def terzaghi_settlement(params, H, sigma0, t, tol=1e-12):
    """Terzaghi(params, H, sigma0).settlement(t): top settlement, m, > 0."""
    return Terzaghi(params, H, sigma0).settlement(t, tol)


# --------------------------------------------------------------------------
# Mandel
# --------------------------------------------------------------------------

def mandel_roots(ratio, n):
    """First n positive roots alpha_1 < alpha_2 < ... of
        tan(alpha) = ratio * alpha,   ratio = (1 - nu) / (nu_u - nu) > 1.

    Root alpha_j lies in ((j-1) pi, (j-1) pi + pi/2) (for j = 1: in (0, pi/2),
    since ratio > 1). It is found by bisection on the pole-free function
        h(alpha) = sin(alpha)/alpha - ratio cos(alpha)
    (h = (sin - ratio alpha cos)/alpha), whose sign at the bracket ends is
    -(-1)^(j-1) at the left (h(0+) = 1 - ratio < 0) and +(-1)^(j-1) at the right.
    All roots are bisected at once (vectorized) until the bracket stops
    shrinking, i.e. to the last bit; the end with the smaller |h| is returned.
    """
    if not ratio > 1.0:
        raise ValueError(f"mandel_roots: ratio = {ratio!r} must be > 1")
    j = np.arange(1, int(n) + 1, dtype=float)
    lo = (j - 1) * math.pi
    hi = lo + math.pi / 2
    parity = np.where(np.arange(int(n)) % 2 == 0, 1.0, -1.0)   # (-1)^(j-1)

    def h(a):
        with np.errstate(invalid="ignore", divide="ignore"):
            s = np.where(a > 0, np.sin(a) / np.where(a > 0, a, 1.0), 1.0)
        return s - ratio * np.cos(a)

    for _ in range(200):
        mid = 0.5 * (lo + hi)
        active = (mid > lo) & (mid < hi)
        if not np.any(active):
            break
        s = h(mid) * parity
        go_left = active & (s > 0)       # root below mid
        go_right = active & (s < 0)
        exact = active & (s == 0)
        hi = np.where(go_left | exact, mid, hi)
        lo = np.where(go_right | exact, mid, lo)
    hl, hh = np.abs(h(lo)), np.abs(h(hi))
    if lo[0] == 0.0:
        hl[0] = np.inf
    return np.where(hl <= hh, lo, hi)


class Mandel(_Consolidation):
    """Mandel's problem (plane strain), after Cheng & Detournay (1988) and
    Abousleiman et al. (1996).

    Geometry and loading: the specimen -a <= x <= a, -b <= y <= b (a, b in m;
    b here is the half-height, not the Biot coefficient params.b) lies between
    rigid, frictionless, impermeable plates at y = +-b. At t = 0 each plate is
    pushed onto the specimen with a total force 2F per unit out-of-plane length
    (F in N/m; mean plate stress F/a, compressive), held constant. The lateral
    sides x = +-a are traction-free and drained (p = 0). Plane strain in z. A
    quarter model 0 <= x <= a, 0 <= y <= b carries force F on its half-plate.
    Mandel.from_traction() takes the mean plate stress sigma = F/a instead.

    With xi = x/a, T = c t / a^2, c = params.c_mandel (= c_v) and the roots
    alpha_n of tan(alpha) = (1 - nu)/(nu_u - nu) alpha (mandel_roots), and
    writing s_n = sin alpha_n, c_n = cos alpha_n, d_n = alpha_n - s_n c_n,
    E_n = exp(-alpha_n^2 T):
      p0     = F B (1 + nu_u) / (3a)                         [Pa]
               (undrained: sigma_yy = -F/a, sigma_xx = 0, sigma_zz = nu_u sigma_yy,
               p0 = -B (mean total stress))
      p      = 2 p0 sum s_n/d_n (cos(alpha_n xi) - c_n) E_n
      u_x    = (F/G) [nu xi/2 - nu_u xi sum s_n c_n/d_n E_n
                      + sum c_n/d_n sin(alpha_n xi) E_n]     [m]
      u_y    = (F/G)(y/a) [-(1 - nu)/2 + (1 - nu_u) sum s_n c_n/d_n E_n]   [m]
      sigma_yy = (F/a) [-1 - 2 (nu_u - nu)/(1 - nu) sum s_n/d_n cos(alpha_n xi) E_n
                        + 2 sum s_n c_n/d_n E_n]              [Pa, tension > 0]
      sigma_xx = sigma_xy = 0.
    Limits: t = 0+: p = p0, u_x = F nu_u x/(2 G a), u_y = -F (1-nu_u) y/(2 G a);
    t -> inf: p = 0, u_x = F nu x/(2 G a), u_y = -F (1-nu) y/(2 G a).
    Mandel-Cryer effect: p(0, t) rises above p0 at early t, then decays like
    2 p0 s_1 (1 - c_1)/d_1 exp(-alpha_1^2 c t/a^2).

    Accuracy: the tail of each series is bounded using |coefficient| <=
    4/(alpha_n - 1/2), alpha_n >= (n-1) pi and alpha_{n+j}^2 - alpha_n^2 >=
    j pi alpha_n: absolute truncation error < tol * p0 (pressure), tol * F/G
    (u_x), tol * F b/(G a) (u_y), tol * F/a (sigma_yy). Small T needs about
    sqrt(ln(1/tol)/T)/pi terms; more than max_terms raises ValueError.
    """

    def __init__(self, params, a, b, F, max_terms=1_000_000):
        if not (a > 0 and b > 0):
            raise ValueError(f"Mandel: half-width a = {a!r} and half-height "
                             f"b = {b!r} must be > 0")
        if not params.b > 0:
            raise ValueError("Mandel: the Biot coefficient must be > 0")
        self.params = params
        self.a = float(a)
        self.b = float(b)
        self.F = float(F)
        self.max_terms = int(max_terms)
        nu, nu_u = params.nu, params.nu_u
        self.ratio = (1.0 - nu) / (nu_u - nu)
        self._roots = np.empty(0)
        self._length = self.a

    @classmethod
    def from_traction(cls, params, a, b, traction, **kw):
        """Mandel problem loaded by a mean plate stress `traction` (Pa,
        compressive positive): F = traction * a."""
        return cls(params, a, b, traction * a, **kw)

    @property
    def c(self):
        """Consolidation coefficient c (Cheng & Detournay 1988), m^2/s."""
        return self.params.c_mandel

    @property
    def p0(self):
        """Undrained initial pressure F B (1 + nu_u) / (3a), Pa."""
        p = self.params
        return self.F * p.B * (1.0 + p.nu_u) / (3.0 * self.a)

    def _find_roots(self, n):
        """alpha_1..alpha_n."""
        return mandel_roots(self.ratio, n)

    def _nterms(self, T, tol):
        """Number of roots needed at time factor T > 0 (see class docstring)."""
        def tail(n):          # bound on the sum over roots n, n+1, ... (n >= 2)
            al = (n - 1) * math.pi
            return 4.0 / (al - 0.5) * math.exp(-al * al * T) / -math.expm1(-math.pi * al * T)
        n = max(2, int(1 + math.sqrt(max(math.log(4.0 / tol), 1.0) / T) / math.pi))
        while tail(n) >= tol:
            n += max(1, n // 50)
        while n > 2 and tail(n - 1) < tol:
            n -= 1
        if n - 1 > self.max_terms:
            raise ValueError(f"Mandel: time factor T = {T:.3e} needs {n - 1} series "
                             f"terms (> max_terms = {self.max_terms})")
        return n - 1

    def _series(self, xi, T, tol, kinds):
        """Sums over roots at flat arrays xi, T (T > 0). kinds: subset of
        'p' (sum s/d (cos(a xi) - c)), 'cos' (sum s/d cos(a xi)),
        'sin' (sum c/d sin(a xi)), 'sc' (sum s c/d); each times E_n."""
        out = {k: np.zeros_like(xi) for k in kinds}
        if xi.size == 0:
            return out
        N = self._nterms(float(T.min()), tol)
        al = self.roots(N)
        chunk = max(1, 1_000_000 // xi.size)
        for i0 in range(0, N, chunk):
            a = al[i0:i0 + chunk]
            s, c = np.sin(a), np.cos(a)
            d = a - s * c
            E = np.exp(-np.outer(T, a * a))              # (points, roots)
            if "p" in out or "cos" in out:
                cosx = np.cos(np.outer(xi, a))
            if "p" in out:
                out["p"] += (E * (cosx - c)) @ (s / d)
            if "cos" in out:
                out["cos"] += (E * cosx) @ (s / d)
            if "sin" in out:
                out["sin"] += (E * np.sin(np.outer(xi, a))) @ (c / d)
            if "sc" in out:
                out["sc"] += E @ (s * c / d)
        return out

    def _prepare(self, x, t, half, name):
        return self._points(x, t, half, -1.0, f"{name} must lie in [{-half}, {half}]")

    def pressure(self, x, t, tol=1e-12):
        """Pore pressure p(x, t), Pa; x in [-a, a] (m), t >= 0 (s), broadcast."""
        xi, T, shape = self._prepare(x, t, self.a, "x")
        P = np.where(np.abs(xi) < 1.0, 1.0, 0.0)       # t = 0
        pos = T > 0
        P[pos] = 2.0 * self._series(xi[pos], T[pos], tol, ["p"])["p"]
        return (self.p0 * P).reshape(shape)

    def displacement_x(self, x, t, tol=1e-12):
        """Horizontal displacement u_x(x, t), m (outward for x > 0)."""
        p = self.params
        xi, T, shape = self._prepare(x, t, self.a, "x")
        U = 0.5 * p.nu_u * xi                           # t = 0
        pos = T > 0
        if np.any(pos):
            S = self._series(xi[pos], T[pos], tol, ["sc", "sin"])
            U[pos] = 0.5 * p.nu * xi[pos] - p.nu_u * xi[pos] * S["sc"] + S["sin"]
        return (self.F / p.G * U).reshape(shape)

    def displacement_y(self, y, t, tol=1e-12):
        """Vertical displacement u_y(y, t), m (negative for y > 0: the plates
        approach); independent of x."""
        p = self.params
        eta, T, shape = self._prepare(y, t, self.b, "y")
        V = np.full_like(eta, -0.5 * (1.0 - p.nu_u))    # t = 0
        pos = T > 0
        if np.any(pos):
            S = self._series(eta[pos], T[pos], tol, ["sc"])
            V[pos] = -0.5 * (1.0 - p.nu) + (1.0 - p.nu_u) * S["sc"]
        return (self.F / p.G * (self.b / self.a) * eta * V).reshape(shape)

    def stress_yy(self, x, t, tol=1e-12):
        """Total vertical stress sigma_yy(x, t), Pa, tension positive
        (negative: the specimen is compressed)."""
        p = self.params
        xi, T, shape = self._prepare(x, t, self.a, "x")
        S_ = np.full_like(xi, -1.0)                     # t = 0
        pos = T > 0
        if np.any(pos):
            S = self._series(xi[pos], T[pos], tol, ["cos", "sc"])
            S_[pos] = (-1.0 - 2.0 * (p.nu_u - p.nu) / (1.0 - p.nu) * S["cos"]
                       + 2.0 * S["sc"])
        return (self.F / self.a * S_).reshape(shape)

    def plate_displacement(self, t, tol=1e-12):
        """Vertical displacement of the top plate u_y(b, t), m (< 0)."""
        return self.displacement_y(self.b, t, tol)

    def lateral_displacement(self, t, tol=1e-12):
        """Horizontal displacement of the drained side u_x(a, t), m (> 0)."""
        return self.displacement_x(self.a, t, tol)


def mandel_pressure(params, a, b, F, x, t, tol=1e-12):
    """Mandel(params, a, b, F).pressure(x, t): pore pressure, Pa."""
    return Mandel(params, a, b, F).pressure(x, t, tol)


def mandel_displacement_x(params, a, b, F, x, t, tol=1e-12):
    """Mandel(params, a, b, F).displacement_x(x, t): u_x, m."""
    return Mandel(params, a, b, F).displacement_x(x, t, tol)


def mandel_displacement_y(params, a, b, F, y, t, tol=1e-12):
    """Mandel(params, a, b, F).displacement_y(y, t): u_y, m."""
    return Mandel(params, a, b, F).displacement_y(y, t, tol)


def mandel_stress_yy(params, a, b, F, x, t, tol=1e-12):
    """Mandel(params, a, b, F).stress_yy(x, t): total sigma_yy, Pa."""
    return Mandel(params, a, b, F).stress_yy(x, t, tol)


# --------------------------------------------------------------------------
# Cryer
# --------------------------------------------------------------------------

def cryer_roots(eta, n):
    """First n positive roots xi_0 < xi_1 < ... of Cryer's equation
        (1 - beta xi^2) sin(xi) = xi cos(xi),   beta = (1 + eta) / (3 eta),
    i.e. tan(xi) = xi / (1 - beta xi^2), for eta > 0.

    With theta(xi) = atan2(xi, 1 - beta xi^2), which increases from 0 to pi,
    the left side minus the right is rho sin(psi), psi = xi - theta(xi),
    rho > 0: the roots are psi(xi) = k pi. psi falls from psi(0) = 0 to its
    only minimum at xi* = 3 sqrt(eta) / (1 + eta) (<= 3/2) and then increases
    to infinity, so psi = k pi has exactly one root for each k = 0, 1, 2, ...
    (k = 0: the positive one), and it lies in [max(k pi, xi*), (k + 1) pi],
    where psi - k pi changes sign. All roots are bisected at once to the last
    bit; the end with the smaller |psi - k pi| is returned.
    """
    if not (eta > 0 and math.isfinite(eta)):
        raise ValueError(f"cryer_roots: eta = {eta!r} must be finite and > 0")
    beta = (1.0 + eta) / (3.0 * eta)
    k = np.arange(int(n), dtype=float)
    target = k * math.pi
    xstar = 3.0 * math.sqrt(eta) / (1.0 + eta)
    lo = np.maximum(target, xstar)
    hi = target + math.pi

    def g(x):
        return x - np.arctan2(x, 1.0 - beta * x * x) - target

    for _ in range(200):
        mid = 0.5 * (lo + hi)
        active = (mid > lo) & (mid < hi)
        if not np.any(active):
            break
        gm = g(mid)
        hi = np.where(active & (gm >= 0), mid, hi)
        lo = np.where(active & (gm < 0), mid, lo)
    return np.where(np.abs(g(lo)) <= np.abs(g(hi)), lo, hi)


def _sin_minus_xcos(x):
    """sin x - x cos x without cancellation at small x (Taylor below 0.1)."""
    x = np.asarray(x, dtype=float)
    small = np.abs(x) < 0.1
    x2 = x * x
    ser = x * x2 * (1.0 / 3.0 - x2 * (1.0 / 30.0 - x2 * (1.0 / 840.0 - x2 / 45360.0)))
    return np.where(small, ser, np.sin(x) - x * np.cos(x))


class Cryer(_Consolidation):
    """Cryer's problem: a poroelastic sphere of radius R, drained (p = 0) on
    its surface, loaded at t = 0 by a uniform compressive radial total stress
    S > 0 (sigma_rr(R, t) = -S), held constant. Radial symmetry: displacement
    u_r(r, t), pressure p(r, t).

    Derivation (checked against the governing equations by
    test_analytical.py). Radial displacement fields are irrotational, so
    equilibrium gives grad(K_v eps - b p) = 0: K_v eps - b p = g(t) for every
    r (eps = div u, K_v = lambda + 2G). Then u_r = r g/(3 K_v) +
    (b/K_v) r^-2 int_0^r p s^2 ds, and sigma_rr(R) = -S fixes
        g = -(K_v/K) S + (4 G b/(3 K)) pbar,   pbar = the volume mean of p,
    K the drained bulk modulus. The mass balance becomes, with
    S_v = 1/M + b^2/K_v and c = (k/mu)/S_v (= c_v of Terzaghi),
        dp/dt + eta dpbar/dt = c lap p,   eta = 4 G b^2 / (3 K K_v S_v),
    p(R) = 0, p(r, 0+) = p0 = B S (undrained: uniform isotropic stress -S,
    no change of fluid content). Its Laplace transform is solved by
    p^ = A (i0(q r) - i0(q R)), i0(z) = sinh z / z, q^2 = s/c; the residues at
    the zeros s_n = -c xi_n^2/R^2 of eta ibar0(qR) - (1+eta) i0(qR)
    (ibar0 the volume mean of i0) give, with rho = r/R, T = c t/R^2 and the
    roots xi_n of (1 - beta xi^2) sin xi = xi cos xi, beta = (1+eta)/(3 eta)
    (cryer_roots):
        p   = p0 sum C_n (j0(xi_n rho) - j0(xi_n)) exp(-xi_n^2 T),
        C_n = 2 (1 + eta) xi_n / ((eta - 2) sin xi_n - (1 + eta) xi_n cos xi_n),
        j0(x) = sin x / x;
        u_r = r g/(3 K_v) + (b R p0/K_v) sum C_n exp(-xi_n^2 T)
              ((sin x - x cos x)/(xi_n^3 rho^2) - j0(xi_n) rho/3),  x = xi_n rho.
    With M = inf and b = 1, beta = (1 - nu)/(2 (1 - 2 nu)): Verruijt's
    equation. Limits: t = 0+: p = p0, u_r = -S r/(3 K_u) (undrained);
    t -> inf: p = 0, u_r = -S r/(3 K). The centre pressure first rises above
    p0 (the Mandel-Cryer effect), then decays like
    p0 C_0 (1 - j0(xi_0)) exp(-xi_0^2 T).

    Accuracy: at the roots |C_n| = 2 (1+eta) sqrt(xi^2 + (1 - beta xi^2)^2)
    / |(1+eta) beta xi^2 - 3|, below 4 (1 + 1/(beta xi) + 1/(beta xi^2)) once
    (1+eta) beta xi^2 >= 6; with xi_n >= n pi the tail from root N on is below
    that bound times 2 exp(-(N pi)^2 T) / (1 - exp(-2 N pi^2 T)): absolute
    truncation error < tol * p0 (pressure), < tol * b R p0 / K_v
    (displacement's series). More than max_terms raises ValueError.

    Time-discrete solution (argument dt of pressure, displacement, ...): the
    problem is linear with a load constant from t = 0+, and its modes
    evolve independently (the generalized eigenproblem of the mass balance
    with the mean-pressure term), so implicit Euler with constant steps dt
    from the undrained state turns exp(-xi_n^2 T) into (1 + xi_n^2 dT)^(-n),
    dT = c dt/R^2, after n = t/dt steps: the solution a discretization exact
    in space would give, against which a run with the same steps shows its
    spatial error alone. Its tail from root N on is below the same cbar
    times 2 (1 + y)^(-n) (1 + N/(2 a n - 1)), y = (N pi)^2 dT,
    a = y/(1 + y) (as 1 + y (k/N)^2 >= (1 + y) (k/N)^(2a) for k >= N).
    """

    def __init__(self, params, R, S, max_terms=1_000_000):
        if not R > 0:
            raise ValueError(f"Cryer: radius R = {R!r} must be > 0")
        if not params.b > 0:
            raise ValueError("Cryer: the Biot coefficient must be > 0")
        self.params = params
        self.R = float(R)
        self.S = float(S)
        self.max_terms = int(max_terms)
        p = params
        self.eta = 4.0 * p.G * p.b ** 2 / (3.0 * p.K_dr * p.K_v * p.S_v)
        self.beta = (1.0 + self.eta) / (3.0 * self.eta)
        self._roots = np.empty(0)
        self._length = self.R

    @property
    def c(self):
        """Consolidation coefficient (k/mu) / S_v, m^2/s."""
        return self.params.c_v

    @property
    def p0(self):
        """Undrained initial pressure B S, Pa."""
        return self.params.B * self.S

    def _find_roots(self, n):
        """xi_0..xi_{n-1}."""
        return cryer_roots(self.eta, n)

    def coefficients(self, n):
        """C_0..C_{n-1} of the pressure series."""
        xi = self.roots(n)
        e = self.eta
        return 2.0 * (1.0 + e) * xi / ((e - 2.0) * np.sin(xi) - (1.0 + e) * xi * np.cos(xi))

    def _nterms(self, T, tol, dT=None):
        """Roots needed at time factor T > 0, or after T/dT implicit Euler
        steps of dT (see the class docstring)."""
        kb = (1.0 + self.eta) * self.beta

        def cbar(x):          # bound on |C_k| for xi_k >= x, (1 + eta) beta x^2 >= 6
            return 4.0 * (1.0 + 1.0 / (self.beta * x) + 1.0 / (self.beta * x * x))

        def tail(n):          # bound on the terms from root n on (pressure: |j0 - j0| <= 2)
            x = n * math.pi
            if dT is None:
                return 2.0 * cbar(x) * math.exp(-x * x * T) / -math.expm1(-2.0 * n * math.pi ** 2 * T)
            steps = T / dT
            y = x * x * dT
            alpha = y / (1.0 + y)
            if 2.0 * alpha * steps <= 1.0:
                return math.inf
            return 2.0 * cbar(x) * math.exp(-steps * math.log1p(y)) * (1.0 + n / (2.0 * alpha * steps - 1.0))
        n = max(1, int(math.ceil(math.sqrt(6.0 / kb) / math.pi)))
        n = max(n, int(math.sqrt(max(math.log(8.0 / tol), 1.0) / T) / math.pi))
        while tail(n) >= tol:
            n += max(1, n // 50)
            if n > self.max_terms:
                raise ValueError(f"Cryer: time factor T = {T:.3e} needs more than max_terms = "
                                 f"{self.max_terms} series terms")
        return n

    def _prepare(self, r, t, dt):
        rho, T, shape = self._points(r, t, self.R, 0.0, "r must lie in [0, R]")
        if dt is not None:
            steps = T / self.time_factor(dt) if dt > 0 else T
            if not dt > 0 or np.any(np.abs(steps - np.round(steps)) > 1e-9 * np.maximum(steps, 1.0)):
                raise ValueError("Cryer: with dt, t must be a multiple of dt > 0")
        return rho, T, shape

    def _series(self, rho, T, tol, kinds, dt=None):
        """Sums over the roots at flat arrays rho, T (T > 0); kinds: 'p'
        (sum C (j0(xi rho) - j0(xi)) E), 'u' (sum C E ((sin x - x cos x)
        / (xi^3 rho^2) - j0(xi) rho/3)), 'mean' (sum C E (jbar0(xi) - j0(xi)),
        jbar0 = 3 (sin xi - xi cos xi)/xi^3, the volume mean of p/p0);
        E = exp(-xi^2 T), or (1 + xi^2 dT)^(-T/dT) with dT = c dt/R^2."""
        out = {k: np.zeros_like(rho) for k in kinds}
        if rho.size == 0:
            return out
        dT = None if dt is None else float(self.time_factor(dt))
        N = self._nterms(float(T.min()), tol, dT)
        xi = self.roots(N)
        C = self.coefficients(N)
        j0 = np.sin(xi) / xi
        chunk = max(1, 1_000_000 // rho.size)
        for i0 in range(0, N, chunk):
            a, cc, jj = xi[i0:i0 + chunk], C[i0:i0 + chunk], j0[i0:i0 + chunk]
            if dT is None:
                E = np.exp(-np.outer(T, a * a)) * cc          # (points, roots)
            else:
                E = np.exp(-np.outer(np.round(T / dT), np.log1p(a * a * dT))) * cc
            x = np.outer(rho, a)
            if "p" in out:
                with np.errstate(invalid="ignore", divide="ignore"):
                    jx = np.where(x > 0, np.sin(x) / np.where(x > 0, x, 1.0), 1.0)
                out["p"] += np.sum(E * (jx - jj), axis=1)
            if "u" in out:
                r2 = np.where(rho > 0, rho * rho, 1.0)[:, None]
                v = _sin_minus_xcos(x) / (a ** 3 * r2) - np.outer(rho, jj) / 3.0
                out["u"] += np.sum(E * np.where(rho[:, None] > 0, v, 0.0), axis=1)
            if "mean" in out:
                out["mean"] += E @ (3.0 * _sin_minus_xcos(a) / a ** 3 - jj)
        return out

    def pressure(self, r, t, tol=1e-12, dt=None):
        """Pore pressure p(r, t), Pa; r in [0, R] (m), t >= 0 (s), broadcast.
        dt [s]: instead, the implicit Euler solution after t/dt steps of dt
        (t a multiple of dt; see the class docstring)."""
        rho, T, shape = self._prepare(r, t, dt)
        P = np.where(rho < 1.0, 1.0, 0.0)                  # t = 0
        pos = T > 0
        P[pos] = self._series(rho[pos], T[pos], tol, ["p"], dt)["p"]
        return (self.p0 * P).reshape(shape)

    def centre_pressure(self, t, tol=1e-12, dt=None):
        """p(0, t), Pa (dt: see pressure)."""
        return self.pressure(0.0, t, tol, dt)

    def mean_pressure(self, t, tol=1e-12, dt=None):
        """Volume mean of p over the sphere, Pa (dt: see pressure)."""
        _, T, shape = self._prepare(0.0, t, dt)
        P = np.ones_like(T)
        pos = T > 0
        P[pos] = self._series(np.zeros(int(np.sum(pos))), T[pos], tol, ["mean"], dt)["mean"]
        return (self.p0 * P).reshape(shape)

    def displacement(self, r, t, tol=1e-12, dt=None):
        """Radial displacement u_r(r, t), m (negative: the sphere shrinks;
        dt: see pressure)."""
        p = self.params
        rho, T, shape = self._prepare(r, t, dt)
        pbar = np.broadcast_to(self.mean_pressure(t, tol, dt), shape).ravel()
        g = -(p.K_v / p.K_dr) * self.S + 4.0 * p.G * p.b / (3.0 * p.K_dr) * pbar
        U = rho * self.R * self.p0 / 3.0 * np.ones_like(rho)   # t = 0: int p s^2 / r^2 = p0 r/3
        pos = T > 0
        if np.any(pos):
            U[pos] = self.R * self.p0 * self._series(rho[pos], T[pos], tol, ["u"], dt)["u"]
        u = rho * self.R * g / (3.0 * p.K_v) + p.b / p.K_v * U
        return u.reshape(shape)


# --------------------------------------------------------------------------
# A pressure-controlled source in a column (steady state)
# --------------------------------------------------------------------------

class SourceColumn:
    """Steady flow in a column 0 < z < L, closed at z = 0, held at p_b at
    z = L, whose part z < a is a pressure-controlled source: the rock there
    takes I (p_w - p) per unit volume and second (geoblock's &source with
    pressure p_w and index I). With m^2 = I mu / k, Darcy's law and the mass
    balance (k/mu) p'' = I (p - p_w) (z < a), p'' = 0 (z > a), p'(0) = 0,
    p(L) = p_b, and p and p' continuous at a give
        p = p_w + A cosh(m z)               (z <= a)
        p = p_b - A m sinh(m a) (L - z)     (z >= a)
        A = (p_b - p_w) / (cosh(m a) + m (L - a) sinh(m a)),
    and the source's rate per unit area of the column, the outflow at L,
        Q = -I A sinh(m a) / m = -(k/mu) A m sinh(m a)    [m/s].
    As I grows the source holds its part at p_w and Q tends to
    (k/mu) (p_w - p_b) / (L - a)."""

    def __init__(self, L, a, p_w, p_b, index, mobility):
        if not (0.0 < a < L and index > 0.0 and mobility > 0.0):
            raise ValueError("SourceColumn needs 0 < a < L, index > 0 and k/mu > 0")
        self.L, self.a, self.p_w, self.p_b = float(L), float(a), float(p_w), float(p_b)
        self.index, self.mobility = float(index), float(mobility)
        self.m = math.sqrt(self.index / self.mobility)
        # A = (p_b - p_w) e^(-m a) 2 / D and the slope outside,
        # G = A m sinh(m a), without overflow for a large m a
        e2 = math.exp(-2.0 * self.m * self.a)
        self._D = 1.0 + e2 + self.m * (self.L - self.a) * (1.0 - e2)
        self.G = (self.p_b - self.p_w) * self.m * (1.0 - e2) / self._D

    def _cosh_part(self, z):
        """A cosh(m z) for 0 <= z <= a."""
        return (self.p_b - self.p_w) * (np.exp(self.m * (z - self.a)) + np.exp(-self.m * (z + self.a))) / self._D

    def _sinh_part(self, z):
        """A sinh(m z) / m for 0 <= z <= a."""
        return (self.p_b - self.p_w) * (np.exp(self.m * (z - self.a)) - np.exp(-self.m * (z + self.a))) / \
            (self.m * self._D)

    def pressure(self, z):
        z = np.asarray(z, dtype=float)
        inner = self.p_w + self._cosh_part(np.clip(z, 0.0, self.a))
        outer = self.p_b - self.G * (self.L - z)
        return np.where(z <= self.a, inner, outer)

    def cell_average(self, z0, z1):
        """The mean of p over [z0, z1] (a cell), exactly."""
        z0, z1 = np.asarray(z0, dtype=float), np.asarray(z1, dtype=float)
        return self.integral(z0, z1) / (z1 - z0)

    def integral(self, z0, z1):
        """The integral of p over [z0, z1] (0 <= z0 < z1 <= L)."""
        def prim(z):
            zi = np.minimum(z, self.a)
            zo = np.maximum(z, self.a)
            inner = self.p_w * zi + self._sinh_part(zi)
            outer = self.p_b * (zo - self.a) + self.G * 0.5 * ((self.L - zo) ** 2 - (self.L - self.a) ** 2)
            return inner + outer
        return prim(z1) - prim(z0)

    def rate(self):
        """The source's rate per unit area of the column [m/s]."""
        return -self.mobility * self.G


# --------------------------------------------------------------------------
# Example plot
# --------------------------------------------------------------------------

EXAMPLE_PARAMS = dict(E=1.0e9, nu=0.25, b=1.0, M=1.0e10, k=1.0e-14, mu=1.0e-3)
EXAMPLE_GEOMETRY = dict(a=1.0, b=1.0, traction=1.0e6)


def plot_mandel_example(path):
    """Write a two-panel PNG: left, p/p0 against time at x = 0, a/2, 0.9a
    (the Mandel-Cryer rise at the centre); right, profiles p(x)/p0 at several
    times. Parameters: EXAMPLE_PARAMS, EXAMPLE_GEOMETRY. Needs matplotlib."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    par = PoroParams(**EXAMPLE_PARAMS)
    g = EXAMPLE_GEOMETRY
    mp = Mandel.from_traction(par, g["a"], g["b"], g["traction"])
    tc = mp.a ** 2 / mp.c                               # s
    t = tc * np.logspace(-5, 1, 400)
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.4))
    for frac, style in [(0.0, "-"), (0.5, "--"), (0.9, ":")]:
        ax1.semilogx(t, mp.pressure(frac * mp.a, t) / mp.p0, style,
                     label=f"x = {frac:g} a")
    ax1.axhline(1.0, color="0.6", lw=0.8)
    ax1.set_xlabel("t [s]")
    ax1.set_ylabel("p / p0")
    ax1.set_title("Mandel: pressure against time")
    ax1.legend()
    ax1.grid(True, which="both", alpha=0.3)
    sec = ax1.secondary_xaxis("top", functions=(lambda s: s / tc, lambda T: T * tc))
    sec.set_xlabel("T = c t / a^2")
    x = np.linspace(0.0, mp.a, 201)
    for T in [1e-3, 1e-2, 0.05, 0.1, 0.3, 0.6, 1.0]:
        ax2.plot(x / mp.a, mp.pressure(x, T * tc) / mp.p0, label=f"T = {T:g}")
    ax2.axhline(1.0, color="0.6", lw=0.8)
    ax2.set_xlabel("x / a")
    ax2.set_ylabel("p / p0")
    ax2.set_title("Mandel: pressure profiles")
    ax2.legend(fontsize=8, loc="lower left")
    ax2.grid(True, alpha=0.3)
    fig.suptitle(f"E = {par.E:.3g} Pa, nu = {par.nu}, b = {par.b}, M = {par.M:.3g} Pa, "
                 f"k = {par.k:.3g} m^2, mu = {par.mu:.3g} Pa s; nu_u = {par.nu_u:.4f}, "
                 f"B = {par.B:.4f}, c = {mp.c:.4g} m^2/s, p0 = {mp.p0:.4g} Pa",
                 fontsize=8.5)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    import argparse
    import os
    ap = argparse.ArgumentParser(description="Analytical Terzaghi and Mandel solutions; run as a script it "
                                 "plots the Mandel example and prints the derived parameters.")
    ap.add_argument("png", nargs="?", default=os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                                           "mandel_example.png"), help="figure file")
    out = ap.parse_args().png
    try:
        plot_mandel_example(out)
    except OSError as e:
        raise SystemExit(f"analytical.py: error: {e}")
    par = PoroParams(**EXAMPLE_PARAMS)
    for key, val in par.summary().items():
        print(f"{key:10s} {val:.6g}")
    print(f"wrote {out}")
