"""Self-check of postproc/analytical.py (Terzaghi, Mandel and Cryer solutions, the
pressure-controlled source in a column).

Run with Debian's Python (numpy, matplotlib):
    /usr/bin/python3 postproc/test_analytical.py
Prints one "  ok    ..." or "  FAIL  ..." line per check and ends with
"suite analytical: N passed, N failed"; exits non-zero on any failure.

Besides the properties asked of the series (initial and final states,
boundary conditions, the diffusion equation by finite differences, the roots),
the Mandel formulas are checked against the governing equations they must
satisfy (sigma_xx = 0, the constitutive law for sigma_yy, the plate force,
the mass balance), and so are Cryer's (radial equilibrium, the surface
stress, the mass balance; for incompressible constituents also Verruijt's
series), so that they do not rest on the printed sources alone.
"""
import math
import os
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import analytical as A  # noqa: E402


class Suite:
    def __init__(self, name):
        self.name = name
        self.passed = 0
        self.failed = 0

    def check(self, ok, what):
        if ok:
            self.passed += 1
            print(f"  ok    {what}")
        else:
            self.failed += 1
            print(f"  FAIL  {what}")

    def close(self, what, a, b, tol):
        """|a - b| <= tol, elementwise (max over arrays)."""
        err = float(np.max(np.abs(np.asarray(a, float) - np.asarray(b, float))))
        ok = bool(np.isfinite(err) and err <= tol)
        self.check(ok, f"{what} (max diff {err:.3e}, tol {tol:.1e})")
        return err

    def below(self, what, value, tol):
        v = float(np.max(np.abs(value)))
        self.check(bool(np.isfinite(v) and v <= tol), f"{what} ({v:.3e} <= {tol:.1e})")

    def raises(self, what, fn):
        try:
            fn()
        except ValueError as e:
            self.check(True, f"{what} -> ValueError: {e}")
            return
        except Exception as e:  # noqa: BLE001
            self.check(False, f"{what}: raised {type(e).__name__} instead of ValueError")
            return
        self.check(False, f"{what}: no error")

    def finish(self):
        print(f"suite {self.name}: {self.passed} passed, {self.failed} failed")
        return 1 if self.failed else 0


# Parameter sets: the example, a Terzaghi-deck-like soil, a stiff rock with a
# compressible fluid and b < 1, incompressible constituents (M = inf).
SETS = {
    "example": A.PoroParams(E=1.0e9, nu=0.25, b=1.0, M=1.0e10, k=1.0e-14, mu=1.0e-3),
    "deck": A.PoroParams(E=1.0e8, nu=0.25, b=1.0, M=1.0e10, k=1.0e-12, mu=1.0e-3),
    "rock": A.PoroParams(E=2.0e10, nu=0.15, b=0.7, M=1.3e10, k=1.0e-17, mu=1.0e-3),
    "incompressible": A.PoroParams(E=1.0e7, nu=0.0, b=1.0, M=math.inf, k=1.0e-12, mu=1.0e-3),
}


def check_params(s):
    print("parameters")
    p = SETS["example"]
    s.close("K_dr = E/(3(1-2nu)), G = E/(2(1+nu)) (example: 6.667e8, 4e8)",
            [p.K_dr / 1e8, p.G / 1e8], [20.0 / 3.0, 4.0], 1e-12)
    for name, p in SETS.items():
        nu, nu_u, b, B = p.nu, p.nu_u, p.b, p.B
        if not math.isinf(p.M):
            s.close(f"[{name}] K_u = K_dr + b^2 M", p.K_u / (p.K_dr + b * b * p.M), 1.0, 1e-14)
            s.close(f"[{name}] nu_u from K_u, G", nu_u,
                    (3 * p.K_u - 2 * p.G) / (2 * (3 * p.K_u + p.G)), 1e-14)
            s.close(f"[{name}] c_v = (k/mu) M K_v/(K_v + b^2 M)", p.c_v /
                    (p.mobility * p.M * p.K_v / (p.K_v + b * b * p.M)), 1.0, 1e-13)
            s.close(f"[{name}] c_v = (k/mu)(K_u-K)(K+4G/3)/(b^2(K_u+4G/3)) (Detournay & Cheng)",
                    p.c_v / (p.mobility * (p.K_u - p.K_dr) * (p.K_dr + 4 * p.G / 3)
                             / (b * b * (p.K_u + 4 * p.G / 3))), 1.0, 1e-12)
        # identities of Detournay & Cheng (1993): independent formulas
        s.close(f"[{name}] nu_u = (3nu + bB(1-2nu))/(3 - bB(1-2nu))", nu_u,
                (3 * nu + b * B * (1 - 2 * nu)) / (3 - b * B * (1 - 2 * nu)), 1e-14)
        s.close(f"[{name}] B = 3(nu_u-nu)/(b(1-2nu)(1+nu_u))", B,
                3 * (nu_u - nu) / (b * (1 - 2 * nu) * (1 + nu_u)), 1e-13)
        s.close(f"[{name}] c_mandel (Cheng & Detournay form) = c_v", p.c_mandel / p.c_v, 1.0, 1e-12)
    p = SETS["incompressible"]
    s.close("[incompressible] nu_u = 1/2, B = 1/b, c_v = (k/mu) K_v / b^2",
            [p.nu_u, p.B, p.c_v / (p.mobility * p.K_v / p.b ** 2)], [0.5, 1.0 / p.b, 1.0], 1e-14)
    big = A.PoroParams(E=1.0e7, nu=0.0, b=1.0, M=1.0e20, k=1.0e-12, mu=1.0e-3)
    s.close("M = 1e20 approaches M = inf (nu_u, B, c_v)",
            [big.nu_u, big.B, big.c_v / p.c_v], [p.nu_u, p.B, 1.0], 1e-11)
    # dimensions: moduli times s and mobility divided by s leave c unchanged;
    # lengths do not enter c at all
    q = SETS["rock"]
    sc = 7.3
    q2 = A.PoroParams(E=q.E * sc, nu=q.nu, b=q.b, M=q.M * sc, k=q.k / sc, mu=q.mu)
    s.close("dimensions: c_v invariant under (moduli * s, k / s)", [q2.c_v / q.c_v,
            q2.c_mandel / q.c_mandel], [1.0, 1.0], 1e-13)
    s.raises("nu = 0.5 rejected", lambda: A.PoroParams(1e9, 0.5, 1.0, 1e10, 1e-15, 1e-3))
    s.raises("b = 1.2 rejected", lambda: A.PoroParams(1e9, 0.2, 1.2, 1e10, 1e-15, 1e-3))
    s.raises("k = 0 rejected", lambda: A.PoroParams(1e9, 0.2, 1.0, 1e10, 0.0, 1e-3))
    d = A.PoroParams.from_namelist(dict(young=1.0e8, poisson=0.25, biot=1.0,
                                        biot_modulus=1.0e10, permeability=1.0e-12,
                                        viscosity=1.0e-3))
    s.check(d == SETS["deck"], "from_namelist maps the deck's &material names")


def d1(f, x, h):
    """Fourth-order central first difference of f at x."""
    return (f(x - 2 * h) - 8 * f(x - h) + 8 * f(x + h) - f(x + 2 * h)) / (12 * h)


def d2(f, x, h):
    """Fourth-order central second difference of f at x."""
    return (-f(x - 2 * h) + 16 * f(x - h) - 30 * f(x) + 16 * f(x + h) - f(x + 2 * h)) / (12 * h * h)


def fd_dt(f, t, rel=5e-3):
    return d1(f, t, rel * t)


def check_terzaghi(s):
    print("Terzaghi")
    for name in ["deck", "rock", "incompressible"]:
        p = SETS[name]
        H, sig = 10.0, 1.0e6
        tz = A.Terzaghi(p, H, sig)
        tc = H * H / p.c_v                      # t = T * tc
        # p0 from the undrained jump: K_v eps - b p = -sigma0, b eps + p/M = 0
        mat = np.array([[p.K_v, -p.b], [p.b, p.inv_M]])
        eps_u, p_u = np.linalg.solve(mat, [-sig, 0.0])
        s.close(f"[{name}] p0 = b M sigma0/(K_v + b^2 M) = undrained solve", tz.p0 / p_u, 1.0, 1e-13)
        z_in = np.linspace(0.0, 0.9 * H, 10)
        s.close(f"[{name}] p(z, 0) = p0 for z < H", tz.pressure(z_in, 0.0) / tz.p0, 1.0, 0.0)
        s.close(f"[{name}] p(z, t = 1e-8 tc) = p0 for z <= 0.9H",
                tz.pressure(z_in, 1e-8 * tc) / tz.p0, 1.0, 1e-12)
        s.below(f"[{name}] p(z, t = 50 tc)/p0 -> 0", tz.pressure(z_in, 50 * tc) / tz.p0, 1e-14)
        ts = tc * np.array([1e-6, 1e-3, 0.1, 0.3, 2.0])
        s.below(f"[{name}] p(H, t) = 0 (drained top)", tz.pressure(H, ts) / tz.p0, 1e-15)
        # dp/dz = 0 at the base: one-sided second-order difference
        h = 1e-3 * H
        for T in [1e-3, 0.05, 0.3, 1.0]:
            t = T * tc
            dpdz = (-3 * tz.pressure(0.0, t) + 4 * tz.pressure(h, t) - tz.pressure(2 * h, t)) / (2 * h)
            s.below(f"[{name}] dp/dz(0) * H/p0 at T = {T:g}", dpdz * H / tz.p0, 1e-7)
        # the diffusion equation by central differences in z and t
        z = np.linspace(0.1, 0.9, 9) * H
        for T in [0.01, 0.1, 0.3, 1.0]:
            t = T * tc
            pt = fd_dt(lambda tt: tz.pressure(z, tt), t)
            pzz = d2(lambda zz: tz.pressure(zz, t), z, 1e-3 * H)
            scale = np.max(np.abs(pt))
            s.below(f"[{name}] (dp/dt - c_v d2p/dz2)/max|dp/dt| at T = {T:g}",
                    (pt - p.c_v * pzz) / scale, 1e-7)
        # displacement: du/dz = (b p - sigma0)/K_v, u(0) = 0, limits
        for T in [0.02, 0.4]:
            t = T * tc
            dudz = d1(lambda zz: tz.displacement(zz, t), z, 1e-3 * H)
            s.below(f"[{name}] du/dz = (b p - sigma0)/K_v at T = {T:g} (rel. sigma0/K_v)",
                    (dudz - (p.b * tz.pressure(z, t) - sig) / p.K_v) * p.K_v / sig, 1e-9)
        s.below(f"[{name}] u(0, t) = 0", tz.displacement(0.0, ts), 0.0)
        s_dr = sig * H / p.K_v
        s_un = 0.0 if math.isinf(p.M) else sig * H / p.K_vu
        s.close(f"[{name}] settlement(0) = sigma0 H / K_vu (undrained)",
                tz.settlement(0.0) / s_dr, s_un / s_dr, 1e-14)
        s.close(f"[{name}] settlement(0+) -> undrained", tz.settlement(1e-12 * tc) / s_dr,
                s_un / s_dr, 1e-5)
        s.close(f"[{name}] settlement(inf) = sigma0 H / K_v (drained)",
                tz.settlement(60 * tc) / s_dr, 1.0, 1e-14)
    # Fourier and image series agree where both are used
    tz = A.Terzaghi(SETS["deck"], 10.0, 1.0e6)
    zeta = np.linspace(0.0, 1.0, 41)
    saved = A._TERZAGHI_T_SWITCH
    try:
        for T in [0.02, 0.1, 0.25, 0.6]:
            TT = np.full_like(zeta, T)
            A._TERZAGHI_T_SWITCH = 0.0
            Pf, If = A._terzaghi_normalized(zeta, TT, 1e-14)
            A._TERZAGHI_T_SWITCH = math.inf
            Pe, Ie = A._terzaghi_normalized(zeta, TT, 1e-14)
            s.close(f"Fourier = erfc series at T = {T:g} (p/p0 and int p/p0)",
                    np.concatenate([Pf, If]), np.concatenate([Pe, Ie]), 2e-14)
    finally:
        A._TERZAGHI_T_SWITCH = saved
    # literature values: T50 = 0.197, T90 = 0.848 (classic tables, 3 digits);
    # small-T asymptote U = 2 sqrt(T/pi)
    tc = 100.0 / tz.c_v
    U = tz.degree_of_consolidation(np.array([0.197, 0.848]) * tc)
    s.close(f"U(T = 0.197) = 0.50, U(T = 0.848) = 0.90 (classic T50, T90; got "
            f"{U[0]:.5f}, {U[1]:.5f})", U, [0.5, 0.9], 1e-3)
    T = np.array([1e-6, 1e-4, 1e-2])
    s.close("U = 2 sqrt(T/pi) for small T", tz.degree_of_consolidation(T * tc),
            2 * np.sqrt(T / np.pi), 1e-13)
    U1 = tz.degree_of_consolidation(1.0 * tc)
    m = np.arange(200)
    s.close("U(T=1) = 1 - sum 8/((2m+1)^2 pi^2) exp(-(2m+1)^2 pi^2 T/4)", U1,
            1 - np.sum(8 / ((2 * m + 1) ** 2 * np.pi ** 2) * np.exp(-(2 * m + 1) ** 2 * np.pi ** 2 / 4)),
            1e-15)
    # vectorization: broadcasting equals pointwise evaluation
    z = np.array([0.0, 2.5, 7.5, 10.0])
    t = tc * np.array([0.0, 1e-3, 0.2, 0.25, 3.0])
    grid = tz.pressure(z[:, None], t[None, :])
    loop = np.array([[tz.pressure(zz, tt) for tt in t] for zz in z])
    s.check(grid.shape == (4, 5) and np.allclose(grid, loop, rtol=0, atol=1e-12 * tz.p0),
            "pressure(z[:,None], t[None,:]) broadcasts and equals pointwise values")
    s.raises("z > H rejected", lambda: tz.pressure(11.0, 1.0))
    s.raises("t < 0 rejected", lambda: tz.pressure(1.0, -1.0))


def h_root(a, r):
    return np.sin(a) - r * a * np.cos(a)


def check_roots(s):
    print("Mandel roots")
    for name, p in SETS.items():
        r = (1 - p.nu) / (p.nu_u - p.nu)
        al = A.mandel_roots(r, 2000)
        j = np.arange(1, al.size + 1)
        lo, hi = (j - 1) * np.pi, (j - 1) * np.pi + np.pi / 2
        s.check(bool(np.all((al > lo) & (al < hi)) and np.all(np.diff(al) > 0)),
                f"[{name}] alpha_j in ((j-1)pi, (j-1)pi + pi/2), increasing (2000 roots, r = {r:.6g})")
        a10 = al[:10]
        s.below(f"[{name}] |tan(alpha) - r alpha|/(r alpha), first 10 roots",
                (np.tan(a10) - r * a10) / (r * a10), 1e-12)
        d = 4 * np.spacing(al)
        s.check(bool(np.all(h_root(al - d, r) * h_root(al + d, r) <= 0)),
                f"[{name}] sin - r alpha cos changes sign within 4 ulp of each of 2000 roots")
        # independent: fixed point alpha = (j-1) pi + arctan(r alpha)
        fp = (j - 1) * np.pi + np.pi / 4
        for _ in range(200):
            fp = (j - 1) * np.pi + np.arctan(r * fp)
        s.close(f"[{name}] roots = fixed-point iteration (j-1)pi + arctan(r alpha), rel.",
                (al - fp) / al, 0.0, 1e-14)
    # tan x = 2x (nu = 0, nu_u = 1/2): a classical root, checked with a
    # high-precision Newton iteration in Python floats from a different start
    al = A.mandel_roots(2.0, 1)[0]
    x = 1.2
    for _ in range(50):
        x -= (math.tan(x) - 2 * x) / (1 / math.cos(x) ** 2 - 2)
    s.close(f"first root of tan x = 2x: {al:.15f} (Newton {x:.15f})", al, x, 4e-16)
    s.raises("ratio <= 1 rejected", lambda: A.mandel_roots(0.9, 3))


def check_mandel(s):
    print("Mandel")
    for name in ["example", "rock", "incompressible"]:
        p = SETS[name]
        a, b, sig = 2.0, 1.0, 1.0e6
        mp = A.Mandel.from_traction(p, a, b, sig)
        F = mp.F
        tc = a * a / mp.c
        # p0 and undrained strains from the 3x3 undrained system
        lam, Kv, bb = p.lam, p.K_v, p.b
        mat = np.array([[Kv, lam, -bb], [lam, Kv, -bb], [bb, bb, p.inv_M]])
        exx, eyy, pu = np.linalg.solve(mat, [0.0, -F / a, 0.0])
        s.close(f"[{name}] p0 = F B (1+nu_u)/(3a) = undrained solve", mp.p0 / pu, 1.0, 1e-13)
        s.close(f"[{name}] u_x(a, 0), u_y(b, 0) = undrained solve",
                [mp.lateral_displacement(0.0) / (exx * a), mp.plate_displacement(0.0) / (eyy * b)],
                [1.0, 1.0], 1e-13)
        x = np.linspace(-0.95, 0.95, 9) * a
        s.close(f"[{name}] p(x, 0) = p0", mp.pressure(x, 0.0) / mp.p0, 1.0, 0.0)
        v = mp.pressure(np.array([0.0, 0.25 * a, 0.5 * a]), 1e-10 * tc) / mp.p0
        s.close(f"[{name}] p(x, T = 1e-10)/p0 = 1 for |x| <= a/2 (rise O(sqrt T))", v, 1.0, 1e-4)
        T0 = 1e-9
        s.close(f"[{name}] series at T = {T0:g} -> undrained u_x(a), u_y(b), sigma_yy",
                [mp.lateral_displacement(T0 * tc) / (exx * a),
                 mp.plate_displacement(T0 * tc) / (eyy * b),
                 mp.stress_yy(0.3 * a, T0 * tc) / (-F / a)], [1.0, 1.0, 1.0], 2e-4)
        ts = tc * np.array([1e-6, 1e-3, 0.05, 0.5, 3.0])
        s.below(f"[{name}] p(+-a, t) = 0", np.concatenate([mp.pressure(a, ts), mp.pressure(-a, ts)])
                / mp.p0, 1e-14)
        s.close(f"[{name}] p(-x, t) = p(x, t)", mp.pressure(-x[:, None], ts[None, :]),
                mp.pressure(x[:, None], ts[None, :]), 1e-14 * mp.p0)
        s.below(f"[{name}] u_x(0, t) = 0 and u_y(0, t) = 0",
                np.concatenate([mp.displacement_x(0.0, ts), mp.displacement_y(0.0, ts)]), 0.0)
        # Mandel-Cryer: the centre pressure rises above p0 early, then decays
        T = np.logspace(-4, 0, 200)
        pc = mp.pressure(0.0, T * tc) / mp.p0
        k = int(np.argmax(pc))
        s.check(bool(pc[k] > 1.0 and pc[0] > 1.0 and T[k] < 0.5),
                f"[{name}] Mandel-Cryer: max p(0,t)/p0 = {pc[k]:.5f} > 1 at T = {T[k]:.3g}")
        s.below(f"[{name}] p(0, T = 30)/p0 -> 0", mp.pressure(0.0, 30 * tc) / mp.p0, 1e-15)
        # late-time decay rate is alpha_1^2, amplitude 2 s1 (1 - c1)/d1
        a1 = mp.roots(1)[0]
        s1, c1 = math.sin(a1), math.cos(a1)
        T1, T2 = 2.0, 3.0
        rate = -math.log(mp.pressure(0.0, T2 * tc) / mp.pressure(0.0, T1 * tc)) / (T2 - T1)
        s.close(f"[{name}] late decay rate of p(0,t) = alpha_1^2 = {a1 * a1:.12f} (got {rate:.12f})",
                rate / (a1 * a1), 1.0, 1e-8)
        amp = 2 * s1 * (1 - c1) / (a1 - s1 * c1) * math.exp(-a1 * a1 * T2)
        s.close(f"[{name}] p(0, T = 3)/p0 = 2 s1(1-c1)/d1 exp(-alpha_1^2 T)",
                mp.pressure(0.0, T2 * tc) / mp.p0 / amp, 1.0, 1e-8)
        # late time: drained state
        s.close(f"[{name}] t -> inf: u_x(a) = F nu/(2G), u_y(b) = -F(1-nu) b/(2 G a), "
                f"sigma_yy = -F/a",
                [mp.lateral_displacement(40 * tc) / (F * p.nu / (2 * p.G)) if p.nu != 0 else 1.0,
                 mp.plate_displacement(40 * tc) / (-F * (1 - p.nu) * b / (2 * p.G * a)),
                 mp.stress_yy(0.5 * a, 40 * tc) / (-F / a)], [1.0, 1.0, 1.0], 1e-12)
        if p.nu == 0:
            s.below(f"[{name}] t -> inf: u_x(a) = 0 (nu = 0)", mp.lateral_displacement(40 * tc)
                    * p.G / F, 1e-14)
        # the governing equations, by finite differences
        xs = np.array([0.0, 0.3, 0.6, 0.85]) * a
        for T in [0.01, 0.1, 0.5]:
            t = T * tc
            def exx_of(tt):
                return d1(lambda xx: mp.displacement_x(xx, tt), xs, 1e-3 * a)

            def eyy_of(tt):
                return mp.plate_displacement(tt) / b
            ex, ey, pp = exx_of(t), eyy_of(t), mp.pressure(xs, t)
            sxx = Kv * ex + lam * ey - bb * pp
            s.below(f"[{name}] sigma_xx = K_v du_x/dx + lam eps_yy - b p = 0 at T = {T:g} "
                    f"(rel. F/a)", sxx * a / F, 1e-9)
            syy = lam * ex + Kv * ey - bb * pp
            s.below(f"[{name}] stress_yy = lam eps_xx + K_v eps_yy - b p at T = {T:g} (rel. F/a)",
                    (mp.stress_yy(xs, t) - syy) * a / F, 1e-9)
            gx, gw = np.polynomial.legendre.leggauss(400)
            force = np.sum(gw * mp.stress_yy(gx * a, t)) * a
            s.close(f"[{name}] int sigma_yy dx = -2F at T = {T:g}", force / (2 * F), -1.0, 1e-10)
            # mass balance (1/M) dp/dt + b d(eps)/dt = (k/mu) d2p/dx2
            pt = fd_dt(lambda tt: mp.pressure(xs, tt), t)
            et = fd_dt(lambda tt: exx_of(tt) + eyy_of(tt), t)
            pxx = d2(lambda xx: mp.pressure(xx, t), xs, 1e-3 * a)
            terms = [p.inv_M * pt, bb * et, p.mobility * pxx]
            scale = max(float(np.max(np.abs(q))) for q in terms)
            s.below(f"[{name}] mass balance (1/M) p_t + b eps_t - (k/mu) p_xx, "
                    f"/ largest term, at T = {T:g}", (terms[0] + terms[1] - terms[2]) / scale, 1e-7)
    # the classical incompressible value p0 = half the plate stress (Mandel 1953)
    mp = A.Mandel.from_traction(SETS["incompressible"], 1.0, 1.0, 3.0e5)
    s.close("incompressible, b = 1: p0 = plate stress / 2", mp.p0, 1.5e5, 1e-9)
    # accuracy control: loose and tight tolerances differ by less than the loose one
    mp = A.Mandel.from_traction(SETS["example"], 1.0, 1.0, 1.0e6)
    tc = 1.0 / mp.c
    x = np.linspace(-1.0, 1.0, 21)
    for T in [1e-5, 1e-2, 0.3]:
        loose = mp.pressure(x, T * tc, tol=1e-6)
        tight = mp.pressure(x, T * tc, tol=1e-14)
        s.below(f"tol = 1e-6 vs 1e-14 at T = {T:g}: |diff|/p0", (loose - tight) / mp.p0, 1e-6)
    # vectorization
    t = tc * np.array([0.0, 1e-4, 0.1, 2.0])
    grid = mp.pressure(x[:, None], t[None, :])
    loop = np.array([[mp.pressure(xx, tt) for tt in t] for xx in x])
    s.check(grid.shape == (21, 4) and np.allclose(grid, loop, rtol=0, atol=1e-12 * mp.p0),
            "pressure(x[:,None], t[None,:]) broadcasts and equals pointwise values")
    s.raises("x > a rejected", lambda: mp.pressure(1.5, 1.0))
    s.raises("t < 0 rejected", lambda: mp.pressure(0.0, -1.0))
    s.raises("too small T for max_terms rejected",
             lambda: A.Mandel.from_traction(SETS["example"], 1.0, 1.0, 1e6,
                                            max_terms=100).pressure(0.0, 1e-8 * tc))
    s.raises("b = 0 rejected", lambda: A.Mandel(A.PoroParams(1e9, 0.2, 0.0, 1e10, 1e-15, 1e-3),
                                                1.0, 1.0, 1.0))


def check_cryer(s):
    print("Cryer")
    # roots for a wide range of eta (the equation's only parameter)
    for eta in [0.01, 0.5248, 2.0, 50.0]:
        beta = (1 + eta) / (3 * eta)
        xi = A.cryer_roots(eta, 2000)
        k = np.arange(xi.size)
        s.check(bool(np.all((xi > k * np.pi) & (xi < (k + 1) * np.pi)) and np.all(np.diff(xi) > 0)),
                f"eta = {eta:g}: xi_k in (k pi, (k+1) pi), increasing (2000 roots)")
        h = (1 - beta * xi ** 2) * np.sin(xi) - xi * np.cos(xi)
        scale = (np.abs(1 - beta * xi ** 2) + xi) * (1 + xi)      # the terms' size times xi's rounding
        s.below(f"eta = {eta:g}: |(1 - beta xi^2) sin xi - xi cos xi| / ((|1 - beta xi^2| + xi)(1 + xi))",
                h / scale, 1e-15)
        d = 1e-12 * xi[:50]
        f = lambda x: (1 - beta * x ** 2) * np.sin(x) - x * np.cos(x)  # noqa: E731
        s.check(bool(np.all(f(xi[:50] - d) * f(xi[:50] + d) < 0)),
                f"eta = {eta:g}: the equation changes sign within 1e-12 xi of each of the first 50 roots")
    s.raises("eta <= 0 rejected", lambda: A.cryer_roots(0.0, 3))
    # incompressible constituents: Verruijt's equation and his centre-pressure series
    # (Theory and Problems of Poroelasticity, Cryer's problem), eta_V = (1 - nu)/(1 - 2 nu)
    for nu in [0.0, 0.25, 0.4]:
        c = A.Cryer(A.PoroParams(E=1e8, nu=nu, b=1.0, M=math.inf, k=1e-12, mu=1e-3), 1.0, 1e6)
        ev = (1 - nu) / (1 - 2 * nu)
        s.close(f"nu = {nu}: 2 beta = (1 - nu)/(1 - 2 nu) (Verruijt's eta)", 2 * c.beta, ev, 1e-14)
        xi = c.roots(400)
        T = np.array([0.01, 0.05, 0.2])
        ver = np.array([np.sum(ev * (np.sin(xi) - xi) / ((ev - 1) * np.sin(xi) + ev * xi * np.cos(xi) / 2)
                               * np.exp(-xi ** 2 * TT)) for TT in T])
        s.close(f"nu = {nu}: p(0, t)/p0 = Verruijt's series at T = 0.01, 0.05, 0.2",
                c.centre_pressure(T * c.R ** 2 / c.c) / c.p0, ver, 1e-12)
    for name in ["example", "rock", "incompressible", "deck"]:
        p = SETS[name]
        R, S = 2.0, 1.0e6
        c = A.Cryer(p, R, S)
        tc = R * R / c.c
        pu = p.b * S / (p.K_dr * p.inv_M + p.b ** 2)      # undrained: -S = K_u eps, p = -b M eps
        s.close(f"[{name}] p0 = B S = b M S / K_u", c.p0 / pu, 1.0, 1e-13)
        r = np.linspace(0.0, 0.9, 10) * R
        s.close(f"[{name}] p(r, 0) = p0", c.pressure(r, 0.0) / c.p0, 1.0, 0.0)
        s.close(f"[{name}] p(r <= 0.9R, T = 1e-10)/p0 = 1 (rise O(sqrt T))", c.pressure(r, 1e-10 * tc) / c.p0,
                1.0, 1e-4)
        ts = tc * np.array([1e-6, 1e-3, 0.05, 0.5, 3.0])
        s.below(f"[{name}] p(R, t) = 0 (drained surface)", c.pressure(R, ts) / c.p0, 1e-14)
        Ku = math.inf if math.isinf(p.M) else p.K_dr + p.b ** 2 * p.M
        s.close(f"[{name}] u(r, 0) = -S r/(3 K_u), u(r, T = 1e-9) -> it (undrained)",
                np.concatenate([c.displacement(r, 0.0), c.displacement(r, 1e-9 * tc)]) * p.K_dr / (S * R),
                np.concatenate([-S * r / (3 * Ku)] * 2) * p.K_dr / (S * R), 2e-5)
        s.close(f"[{name}] t -> inf: p = 0, u = -S r/(3 K) (drained)",
                np.concatenate([c.pressure(r, 40 * tc) / c.p0, c.displacement(r, 40 * tc) * 3 * p.K_dr / (S * R)]),
                np.concatenate([0 * r, -r / R]), 1e-13)
        s.below(f"[{name}] u(0, t) = 0", c.displacement(0.0, ts), 0.0)
        # Mandel-Cryer: the centre pressure rises above p0 early, then decays
        T = np.logspace(-4, 0, 200)
        pc = c.centre_pressure(T * tc) / c.p0
        k = int(np.argmax(pc))
        s.check(bool(pc[k] > 1.0 and pc[0] > 1.0 and T[k] < 0.2),
                f"[{name}] Mandel-Cryer: max p(0,t)/p0 = {pc[k]:.5f} > 1 at T = {T[k]:.3g}")
        s.below(f"[{name}] p(0, T = 30)/p0 -> 0", c.centre_pressure(30 * tc) / c.p0, 1e-15)
        x0 = c.roots(1)[0]
        C0 = c.coefficients(1)[0]
        T1, T2 = 2.0, 3.0
        rate = -math.log(c.centre_pressure(T2 * tc) / c.centre_pressure(T1 * tc)) / (T2 - T1)
        s.close(f"[{name}] late decay of p(0,t): rate xi_0^2 = {x0 * x0:.10f}, amplitude C_0 (1 - j0(xi_0))",
                [rate / x0 ** 2, c.centre_pressure(T2 * tc) / c.p0 / (C0 * (1 - math.sin(x0) / x0)
                                                                      * math.exp(-x0 * x0 * T2))],
                [1.0, 1.0], 1e-8)
        # the governing equations by finite differences
        lam, G, b = p.lam, p.G, p.b
        rs = np.array([0.2, 0.45, 0.7, 0.9]) * R
        hr = 1e-3 * R
        for T in [0.01, 0.1, 0.5]:
            t = T * tc

            def strain(tt, rr=rs):
                du = d1(lambda x: c.displacement(x, tt), rr, hr)
                return du, c.displacement(rr, tt) / rr

            du, ur = strain(t)
            pp = c.pressure(rs, t)
            srr = lambda x: (lam + 2 * G) * d1(lambda y: c.displacement(y, t), x, hr) \
                + 2 * lam * c.displacement(x, t) / x - b * c.pressure(x, t)      # noqa: E731
            stt = lam * du + 2 * (lam + G) * ur - b * pp
            eq = d1(srr, rs, hr) + 2 * (srr(rs) - stt) / rs
            s.below(f"[{name}] equilibrium d sigma_rr/dr + 2 (sigma_rr - sigma_tt)/r = 0 at T = {T:g} "
                    f"(rel. S/R)", eq * R / S, 1e-6)
            # at the surface: one-sided (backward) fourth-order difference of u
            x = np.array([R])
            dR = (25 * c.displacement(x, t) - 48 * c.displacement(x - hr, t) + 36 * c.displacement(x - 2 * hr, t)
                  - 16 * c.displacement(x - 3 * hr, t) + 3 * c.displacement(x - 4 * hr, t)) / (12 * hr)
            sR = (lam + 2 * G) * dR + 2 * lam * c.displacement(x, t) / R
            s.close(f"[{name}] sigma_rr(R) = -S at T = {T:g}", sR / S, -1.0, 1e-7)
            pt = fd_dt(lambda tt: c.pressure(rs, tt), t)
            et = fd_dt(lambda tt: sum(strain(tt)[0:1]) + 2 * strain(tt)[1], t)
            lap = d2(lambda x: c.pressure(x, t), rs, hr) + 2 / rs * d1(lambda x: c.pressure(x, t), rs, hr)
            terms = [p.inv_M * pt, b * et, p.mobility * lap]
            scale = max(float(np.max(np.abs(q))) for q in terms)
            s.below(f"[{name}] mass balance (1/M) p_t + b eps_t - (k/mu) lap p, / largest term, at T = {T:g}",
                    (terms[0] + terms[1] - terms[2]) / scale, 1e-6)
    # the implicit Euler solution: the time-discrete mass balance at step n,
    # (1/M)(p_n - p_(n-1))/dt + b (eps_n - eps_(n-1))/dt = (k/mu) lap p_n, with
    # eps = du/dr + 2u/r from its displacement; and dt -> 0 gives the series
    for name in ["example", "rock"]:
        p = SETS[name]
        R = 2.0
        c = A.Cryer(p, R, 1.0e6)
        tc = R * R / c.c
        rs = np.array([0.2, 0.45, 0.7, 0.9]) * R
        hr = 1e-3 * R
        for dT, n in [(1e-3, 50), (0.02, 10)]:
            dt = dT * tc

            def eps(k):
                u = lambda x: c.displacement(x, k * dt, dt=dt)  # noqa: E731
                return d1(u, rs, hr) + 2 * u(rs) / rs

            pn = lambda x: c.pressure(x, n * dt, dt=dt)  # noqa: E731
            terms = [p.inv_M * (pn(rs) - c.pressure(rs, (n - 1) * dt, dt=dt)) / dt,
                     p.b * (eps(n) - eps(n - 1)) / dt,
                     p.mobility * (d2(pn, rs, hr) + 2 / rs * d1(pn, rs, hr))]
            scale = max(float(np.max(np.abs(q))) for q in terms)
            s.below(f"[{name}] implicit Euler ({n} steps of c dt/R^2 = {dT:g}): the time-discrete mass balance, "
                    f"/ largest term", (terms[0] + terms[1] - terms[2]) / scale, 1e-6)
        t = 0.05 * tc
        s.close(f"[{name}] implicit Euler with 1e5 steps -> the series (p(r, T = 0.05)/p0)",
                c.pressure(rs, t, dt=t / 1e5) / c.p0, c.pressure(rs, t) / c.p0, 1e-5)
        s.raises(f"[{name}] t not a multiple of dt rejected", lambda: c.pressure(0.0, 1.5, dt=1.0))
    # accuracy control and vectorization
    c = A.Cryer(SETS["example"], 1.0, 1.0e6)
    tc = 1.0 / c.c
    r = np.linspace(0.0, 1.0, 21)
    for T in [1e-5, 1e-2, 0.3]:
        s.below(f"tol = 1e-6 vs 1e-14 at T = {T:g}: |diff|/p0",
                (c.pressure(r, T * tc, tol=1e-6) - c.pressure(r, T * tc, tol=1e-14)) / c.p0, 1e-6)
    t = tc * np.array([0.0, 1e-4, 0.1, 2.0])
    grid = c.displacement(r[:, None], t[None, :])
    loop = np.array([[c.displacement(rr, tt) for tt in t] for rr in r])
    s.check(grid.shape == (21, 4) and np.allclose(grid, loop, rtol=0, atol=1e-15),
            "displacement(r[:,None], t[None,:]) broadcasts and equals pointwise values")
    s.raises("r > R rejected", lambda: c.pressure(1.5, 1.0))
    s.raises("t < 0 rejected", lambda: c.pressure(0.0, -1.0))
    s.raises("b = 0 rejected", lambda: A.Cryer(A.PoroParams(1e9, 0.2, 0.0, 1e10, 1e-15, 1e-3), 1.0, 1.0))


def check_source_column(s):
    """SourceColumn against the equations it solves (finite differences, a
    quadrature of the source) and its limit of a held source."""
    L, a, pw, pb, idx, mob = 12.0, 4.0, 3.0e6, 0.5e6, 2.0e-11, 3.0e-11
    sc = A.SourceColumn(L, a, pw, pb, idx, mob)
    h = 1e-3
    zi = np.linspace(0.3, a - 0.3, 7)
    zo = np.linspace(a + 0.3, L - 0.3, 7)
    lhs_i = np.array([mob * d2(sc.pressure, z, h) for z in zi])
    rhs_i = idx * (sc.pressure(zi) - pw)
    s.check(np.allclose(lhs_i, rhs_i, rtol=1e-5, atol=1e-9 * idx * abs(pw - pb)),
            "source column: (k/mu) p'' = I (p - p_w) in the source (finite differences)")
    s.check(np.allclose([d2(sc.pressure, z, h) for z in zo], 0.0, atol=1e-7 * abs(pw - pb) / L ** 2),
            "source column: p'' = 0 outside the source")
    hf = 1e-4
    slope0 = (-3.0 * sc.pressure(0.0) + 4.0 * sc.pressure(hf) - sc.pressure(2.0 * hf)) / (2.0 * hf)
    s.check(abs(slope0) < 1e-6 * abs(pw - pb) / L, "source column: no flow at z = 0 (one-sided difference)")
    s.check(abs(float(sc.pressure(L)) - pb) < 1e-9 * abs(pw - pb), "source column: p = p_b at z = L")
    jump = abs(float(sc.pressure(a - 1e-9)) - float(sc.pressure(a + 1e-9)))
    slopes = (d1(sc.pressure, a - 2e-3, 1e-3), d1(sc.pressure, a + 2e-3, 1e-3))
    s.check(jump < 1e-6 * abs(pw - pb) and abs(slopes[0] - slopes[1]) < 1e-2 * abs(slopes[1]),
            "source column: p and p' continuous at z = a")
    g, w = np.polynomial.legendre.leggauss(40)
    zq = 0.5 * a * (g + 1.0)
    inflow = 0.5 * a * np.sum(w * idx * (pw - sc.pressure(zq)))
    outflow = -mob * d1(sc.pressure, L - 1e-3, 1e-3)
    s.check(abs(inflow - sc.rate()) < 1e-10 * abs(sc.rate()) and abs(outflow - sc.rate()) < 1e-6 * abs(sc.rate()),
            f"source column: rate {sc.rate():.6e} m/s = the source's integral = the outflow at z = L")
    z0 = np.array([0.0, 3.5, 3.9, 9.0])
    z1 = np.array([0.7, 4.5, 4.1, 12.0])
    quad = np.array([0.5 * np.sum(w * sc.pressure(0.5 * (lo + hi) + 0.5 * (hi - lo) * g))
                     for lo, hi in zip(z0, z1)])
    s.check(np.allclose(sc.cell_average(z0, z1), quad, rtol=0, atol=1e-6 * abs(pw - pb)),
            "source column: cell averages (across z = a too) against Gauss quadrature")
    held = A.SourceColumn(L, a, pw, pb, 1e8 * idx, mob)
    s.check(abs(held.rate() - mob * (pw - pb) / (L - a)) < 1e-3 * abs(held.rate())
            and abs(float(held.pressure(0.5 * a)) - pw) < 1e-6 * abs(pw - pb),
            "source column: a large index holds the source at p_w, Q -> (k/mu)(p_w - p_b)/(L - a)")


def check_plot(s):
    print("plot")
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        s.check(False, "matplotlib importable (use /usr/bin/python3)")
        return
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "mandel.png")
        A.plot_mandel_example(path)
        ok = os.path.exists(path)
        size = os.path.getsize(path) if ok else 0
        with open(path, "rb") as f:
            sig = f.read(8) if ok else b""
        s.check(ok and sig == b"\x89PNG\r\n\x1a\n" and size > 10_000,
                f"plot_mandel_example writes a PNG ({size} bytes)")


def main():
    import argparse
    argparse.ArgumentParser(description="Self-checks of postproc/analytical.py (Terzaghi, Mandel, Cryer); one line "
                            "per check and a summary.").parse_args()
    s = Suite("analytical")
    np.seterr(all="raise", under="ignore")
    for part in (check_params, check_terzaghi, check_roots, check_mandel, check_cryer, check_source_column,
                 check_plot):
        try:
            part(s)
        except Exception as e:  # noqa: BLE001  a crash counts as a failure
            import traceback
            traceback.print_exc()
            s.check(False, f"{part.__name__} crashed: {type(e).__name__}: {e}")
    return s.finish()


if __name__ == "__main__":
    sys.exit(main())
