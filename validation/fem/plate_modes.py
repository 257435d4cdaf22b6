"""Oscillating plate (cantilever, TL paper sec. 4.1, Table 2): small-amplitude period, plane strain.

The first bending eigenfrequency omega_1 of the 2D plate of the SPH case `oscillating-plate-2d`
(crates/sph-cases/src/cases/oscillating_plate_2d.rs), T = 2 pi / omega_1, from linear
elasticity with P2 triangles (scikit-fem), a mesh study and Richardson extrapolation. It is the
v_f -> 0 limit of the SPH runs (which start with a first-mode velocity of tip speed v_f c0,
v_f = 0.01...0.15); large amplitude is not modelled. See README.md, "Oscillating plate".

Plate: free length L = 0.2 m, thickness H = 0.02 m (and the thin plate H = 0.01 m of the TL
paper's Table 2), rho0 = 1000 kg/m^3, E = 2 MPa, nu in {0.22, 0.3, 0.3975, 0.4}; the strip
continues SL = 0.06 m into the base. Clamps (case key `clamp`):
  solid  every point with x < 0 fixed: domain [0, L] x [-H/2, H/2], u = 0 on x = 0;
  frame  the embedded strip [-SL, 0] x [-H/2, H/2] is free material held by a rigid frame
         around it: domain [-SL, L] x [-H/2, H/2], u = 0 on y = +-H/2 for -SL <= x <= 0 and on
         x = -SL (the SPH frame: 4 fixed particle layers; continuum limit: a bonded rigid wall).
Two small-strain laws (in-plane stress; README.md lists which SPH method has which):
  hooke     plane-strain Hooke: lambda = E nu / ((1 + nu)(1 - 2 nu)), mu = E / (2 (1 + nu));
  d2-split  the d = 2 volumetric-deviatoric split: sigma = K tr(eps) I + 2 G (eps - tr(eps)/2 I),
            K = E / (3 (1 - 2 nu)), G = mu, i.e. lambda_eff = K - G.
The bending modes are antisymmetric about y = 0, so the mesh study uses the half model
0 <= y <= H/2 with u_x = 0 on y = 0 (checked against the full model).

    python3 validation/fem/plate_modes.py            # -> validation/results/fem-plate-modes.json
    python3 validation/fem/plate_modes.py --quick    # coarse meshes, one nu, no JSON (smoke test)
"""
from __future__ import annotations

import argparse
import math
import os
import sys

import numpy as np
import scipy.linalg as sla
import scipy.optimize as sopt
import scipy.sparse.linalg as spla
from skfem import Basis, BilinearForm, ElementTriP2, ElementVector, MeshTri, asm
from skfem.helpers import dot, sym_grad

import common as C

# ----------------------------------------------------------------------------- the case
L = 0.2            # free length (m)
SL = 0.06          # length of the strip inside the base (m), case key base_length
RHO = 1000.0       # rho0 (kg/m^3)
E_MOD = 2.0e6      # E (Pa)
NUS = (0.22, 0.3, 0.3975, 0.4)
THICKNESSES = (0.02, 0.01)
CLAMPS = ("solid", "frame")
LAWS = ("hooke", "d2-split")
KL_CODE = 1.875    # kL of the code's thin-plate period (oscillating_plate_2d.rs, KL)

# ----------------------------------------------------------------------------- mesh study
LEVELS = {"solid": (0, 1, 2, 3), "frame": (0, 1, 2, 3, 4)}  # frame: slower (order ~1)
NY_HALF = 4        # base: cells across the half thickness ...
GRADING_Y = 4.0    # ... graded 4:1 toward the face y = H/2
NX_FREE = 20       # base: cells along the free length [0, L] ...
NX_BASE = 6        # ... and along the embedded strip [-SL, 0] (frame clamp) ...
GRADING_X = 32.0   # ... graded 32 (0.02 m / H):1 toward x = 0 (the singular points at x = 0;
                   # the smallest cell is H/19 for H = 0.02 and H/16 for H = 0.01)


def law_constants(law, nu):
    """(lambda, mu) of the in-plane small-strain law."""
    mu = E_MOD / (2.0 * (1.0 + nu))
    if law == "hooke":
        return E_MOD * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), mu
    if law == "d2-split":
        k = E_MOD / (3.0 * (1.0 - 2.0 * nu))
        return k - mu, mu
    raise ValueError(law)


def bending_modulus(lam, mu):
    """In-plane uniaxial-stress modulus of the 2D law (sigma_yy = 0): 4 mu (lam + mu)/(lam + 2 mu)
    (= E/(1 - nu^2) for plane-strain Hooke) and the in-plane Poisson ratio lam/(lam + 2 mu)."""
    return 4.0 * mu * (lam + mu) / (lam + 2.0 * mu), lam / (lam + 2.0 * mu)


def bending_modulus_c(cmat):
    """The same for (C11, C12, C66) with C22 = C11: C11 - C12^2/C11."""
    c11, c12, _ = cmat
    return c11 - c12 * c12 / c11


def graded(a, b, n, ratio, fine_at):
    """n + 1 points on [a, b], spacing geometric (largest/smallest = ratio), finest at the end
    `fine_at` ('a' or 'b'). The points are the images of a uniform parameter grid, so doubling
    n nests them."""
    s = np.linspace(0.0, 1.0, n + 1)
    if ratio == 1.0:
        t = s
    else:
        beta = math.log(ratio)
        t = (np.exp(beta * s) - 1.0) / (ratio - 1.0)  # spacing grows toward s = 1
        t[-1] = 1.0
    if fine_at == "b":
        t = 1.0 - t[::-1]
    return a + (b - a) * t


def grid_mesh(xs, ys):
    """Tensor grid triangulated with the diagonal pointing away from y = 0 (so that the mesh
    mirrored about y = 0 is the full model's mesh)."""
    X, Y = np.meshgrid(xs, ys, indexing="ij")
    p = np.vstack([X.ravel(), Y.ravel()])
    idx = np.arange(len(xs) * len(ys)).reshape(len(xs), len(ys))
    i, j = np.meshgrid(np.arange(len(xs) - 1), np.arange(len(ys) - 1), indexing="ij")
    i, j = i.ravel(), j.ravel()
    a, b, c, d = idx[i, j], idx[i + 1, j], idx[i + 1, j + 1], idx[i, j + 1]
    up = 0.5 * (ys[j] + ys[j + 1]) > 0
    t1 = np.where(up, np.vstack([a, b, c]), np.vstack([a, b, d]))
    t2 = np.where(up, np.vstack([a, c, d]), np.vstack([b, c, d]))
    return MeshTri(p, np.hstack([t1, t2]))


def base_axes(clamp, H, full):
    """Base grid lines. x: the free part [0, L] with NX_FREE cells graded GRADING_X (0.02/H):1
    toward the root x = 0; the frame clamp adds [-SL, 0] with NX_BASE cells graded the same way
    toward x = 0 (the same cells on [0, L] for both clamps). y: NY_HALF cells over [0, H/2] graded
    GRADING_Y:1 toward y = H/2 (mirrored for the full model). The singular points of the
    solution (solid: the clamped-free corners (0, +-H/2); frame: the points (0, +-H/2) where
    the faces change from bonded to free) get the smallest cells."""
    gx = GRADING_X * 0.02 / H
    xs = graded(0.0, L, NX_FREE, gx, "a")
    if clamp == "frame":
        xs = np.concatenate([graded(-SL, 0.0, NX_BASE, gx, "b")[:-1], xs])
    yh = graded(0.0, H / 2, NY_HALF, GRADING_Y, "b")
    ys = np.concatenate([-yh[:0:-1], yh]) if full else yh
    return xs, ys


def plate_mesh(clamp, H, level, full=False):
    xs, ys = base_axes(clamp, H, full)
    m = grid_mesh(xs, ys)
    return m.refined(level) if level > 0 else m


# ----------------------------------------------------------------------------- FE solve
def stiffness_matrix(lam, mu):
    """In-plane stiffness (C11, C12, C66) of an isotropic 2D law: sigma_xx = C11 e_xx + C12 e_yy,
    sigma_yy = C12 e_xx + C11 e_yy, sigma_xy = 2 C66 e_xy."""
    return lam + 2.0 * mu, lam, mu


def _forms(cmat):
    c11, c12, c66 = cmat

    @BilinearForm
    def stiffness(u, v, w):
        eu, ev = sym_grad(u), sym_grad(v)
        sxx = c11 * eu[0, 0] + c12 * eu[1, 1]
        syy = c12 * eu[0, 0] + c11 * eu[1, 1]
        sxy = 2.0 * c66 * eu[0, 1]
        return sxx * ev[0, 0] + syy * ev[1, 1] + 2.0 * sxy * ev[0, 1]

    @BilinearForm
    def mass(u, v, w):
        return RHO * dot(u, v)

    return stiffness, mass


def fixed_dofs(basis, mesh, clamp, H, full):
    """Dirichlet dofs: the clamp's faces (both components) and, for the half model, u_x on
    y = 0 (antisymmetry of the bending modes)."""
    bf = mesh.boundary_facets()
    mid = mesh.p[:, mesh.facets[:, bf]].mean(axis=1)
    eps = 1e-9 * L
    if clamp == "solid":
        clamp_f = bf[np.abs(mid[0]) < eps]
    else:
        face = (np.abs(np.abs(mid[1]) - H / 2) < eps) & (mid[0] < 0.0)
        back = np.abs(mid[0] + SL) < eps
        clamp_f = bf[face | back]
    dofs = [basis.get_dofs(facets=clamp_f).all()]
    if not full:
        axis = bf[np.abs(mid[1]) < eps]
        dofs.append(basis.get_dofs(facets=axis).all(["u^1"]))
    return np.unique(np.concatenate(dofs)), len(clamp_f)


def system(clamp, H, level, cmat, full=False):
    """Mesh, basis, stiffness and mass matrices and the free dofs."""
    mesh = plate_mesh(clamp, H, level, full)
    basis = Basis(mesh, ElementVector(ElementTriP2()), intorder=4)
    stiffness, mass = _forms(cmat)
    K = asm(stiffness, basis).tocsr()
    M = asm(mass, basis).tocsr()
    fixed, nclamp = fixed_dofs(basis, mesh, clamp, H, full)
    free = np.setdiff1d(np.arange(basis.N), fixed)
    return mesh, basis, K, M, free, nclamp


def eigen(clamp, H, level, cmat, full=False, k=1, want_vector=False):
    """Lowest k eigenpairs of K phi = omega^2 M phi for the in-plane stiffness cmat
    (C11, C12, C66). Returns (omega^2 array, info, mode data) and, with want_vector,
    (basis, M, phi_1 on all dofs)."""
    clock = C.Clock()
    mesh, basis, K, M, free, nclamp = system(clamp, H, level, cmat, full)
    Kff = K[free][:, free].tocsc()
    Mff = M[free][:, free].tocsc()
    vals, vecs = spla.eigsh(Kff, k=k, M=Mff, sigma=0.0, which="LM")
    o = np.argsort(vals)
    vals, vecs = vals[o], vecs[:, o]
    # tip displacements of the first mode at (L, 0) (u_y) and the largest |u_x| on x = L
    phi = np.zeros(basis.N)
    phi[free] = vecs[:, 0]
    ux, uy = basis.nodal_dofs[0], basis.nodal_dofs[1]
    tip = np.nonzero((np.abs(mesh.p[0] - L) < 1e-12) & (np.abs(mesh.p[1]) < 1e-12))[0]
    end = np.abs(mesh.p[0] - L) < 1e-12
    tip_uy = float(phi[uy[tip[0]]])
    end_ux = float(np.max(np.abs(phi[ux[end]])))
    max_uy = float(np.max(np.abs(phi[basis.nodal_dofs[1]])))
    info = {"level": level, "dofs": int(basis.N), "free_dofs": int(len(free)),
            "elements": int(mesh.t.shape[1]), "h_min": float(_h_min(mesh)),
            "clamp_facets": int(nclamp), "seconds": clock()}
    mode = {"tip_uy": tip_uy, "end_max_abs_ux": end_ux, "max_abs_uy": max_uy}
    if want_vector:
        return vals, info, mode, (basis, M, phi, tip[0])
    return vals, info, mode


def mode_shape(x):
    """The SPH initial velocity profile f(x)/f(L) (TL eq 35, kL = 1.875;
    oscillating_plate_2d.rs mode_shape, first_mode_velocities): zero for x <= 0."""
    k, kl = KL_CODE / L, KL_CODE
    f = lambda s: ((math.sin(kl) + math.sinh(kl)) * (np.cos(k * s) - np.cosh(k * s))
                   - (math.cos(kl) + math.cosh(kl)) * (np.sin(k * s) - np.sinh(k * s)))
    return np.where(x > 0.0, f(x) / f(L), 0.0)


def initial_velocity_projection(clamp, H, level, cmat):
    """Share of the SPH initial velocity field v0 = (0, f(x)/f(L)) (x > 0) that is mode 1:
    kinetic-energy fraction (phi_1' M v0)^2 / ((phi_1' M phi_1)(v0' M v0)) and the mode-1 part
    of the tip velocity."""
    vals, _, _, (basis, M, phi, tip) = eigen(clamp, H, level, cmat, want_vector=True)
    v0 = np.zeros(basis.N)
    uy = basis.nodal_dofs[1]
    fy = np.concatenate([basis.nodal_dofs[1], basis.facet_dofs[1]])
    v0[fy] = mode_shape(basis.doflocs[0, fy])
    a = phi @ (M @ v0) / (phi @ (M @ phi))
    frac = a * a * (phi @ (M @ phi)) / (v0 @ (M @ v0))
    return {"clamp": clamp, "H": H, "level": level, "kinetic_energy_fraction_mode_1": float(frac),
            "tip_velocity_fraction_mode_1": float(a * phi[uy[tip]] / v0[uy[tip]])}


def _h_min(mesh):
    e = mesh.p[:, mesh.facets[0]] - mesh.p[:, mesh.facets[1]]
    return np.min(np.hypot(e[0], e[1]))


def period(omega2):
    return 2.0 * math.pi / math.sqrt(omega2)


# ----------------------------------------------------------------------------- beam theory
def kl_root():
    """First root of cos x cosh x + 1 = 0 (clamped-free Euler-Bernoulli beam)."""
    return sopt.brentq(lambda x: math.cos(x) * math.cosh(x) + 1.0, 1.5, 2.2, xtol=1e-15)


def euler_bernoulli_period(H, e_bend, kl):
    """T = 2 pi / omega, omega^2 = E' H^2 k^4 / (12 rho), k = kl / L (TL eq 37 with E' for
    E/(1 - nu^2))."""
    k = kl / L
    return 2.0 * math.pi / math.sqrt(e_bend * H * H * k ** 4 / (12.0 * RHO))


def timoshenko_omega(H, e_bend, g, kappa, rotary=True):
    """First eigenfrequency of a clamped-free Timoshenko beam (per unit depth: A = H,
    I = H^3/12), from the transfer matrix of y = (w, psi, M, Q):
    w' = psi + Q/(kappa G A), psi' = M/(E' I), M' = -Q - omega^2 rho I psi, Q' = -omega^2 rho A w;
    w = psi = 0 at x = 0, M = Q = 0 at x = L."""
    A, I = H, H ** 3 / 12.0
    ei, kga = e_bend * I, kappa * g * A
    rI = RHO * I if rotary else 0.0

    def det(omega):
        w2 = omega * omega
        Amat = np.array([[0.0, 1.0, 0.0, 1.0 / kga],
                         [0.0, 0.0, 1.0 / ei, 0.0],
                         [0.0, -w2 * rI, 0.0, -1.0],
                         [-w2 * RHO * A, 0.0, 0.0, 0.0]])
        Phi = sla.expm(Amat * L)
        return Phi[2, 2] * Phi[3, 3] - Phi[2, 3] * Phi[3, 2]

    w_eb = 2.0 * math.pi / euler_bernoulli_period(H, e_bend, kl_root())
    grid = np.linspace(0.5 * w_eb, 1.2 * w_eb, 141)
    vals = [det(w) for w in grid]
    for a, b, fa, fb in zip(grid[:-1], grid[1:], vals[:-1], vals[1:]):
        if fa * fb < 0:
            return sopt.brentq(det, a, b, xtol=1e-14 * w_eb, rtol=1e-14)
    raise RuntimeError("no Timoshenko root bracketed")


def cowper_kappa(nu2d):
    """Cowper's shear coefficient of a rectangle, 10 (1 + nu)/(12 + 11 nu), with the in-plane
    Poisson ratio of the 2D law."""
    return 10.0 * (1.0 + nu2d) / (12.0 + 11.0 * nu2d)


# ----------------------------------------------------------------------------- SPH lattice limit
# Informative, not a reference: what the SPH methods' bulk operators become at small strain on
# the undisturbed square lattice at their fixed h/dp (the limit dp -> 0 at fixed h/dp, away from
# boundaries). Derivation in README.md, "SPH methods and the two laws".
TL_H_OVER_DP, TL_HF_ZETA = 1.15, 1.07  # tl_common h_over_dp; hourglass_free::DEFAULT_ZETA
UL_H_OVER_DP, UL_ENOG_ZETA = 1.3, 0.7 * 2 + 2.1  # ul_h_over_dp; non_nested::default_zeta(2)
LATTICE_LEVEL = 2


def lattice_moments(h_over_dp):
    """Sums over the neighbours j != i of a particle of the square lattice (dp = 1, V_j = 1) of the
    2D Wendland C2 kernel (support 2h, W = 7/(4 pi h^2) (1 - q/2)^4 (1 + 2q)), e = unit vector:
    m2 = sum r W' e_x^2 (continuum -1), m4_1111 = sum r W' e_x^4 (-3/4),
    m4_1122 = sum r W' e_x^2 e_y^2 (-1/4), sum_W = sum over all j (self included) of W (1)."""
    h = h_over_dp
    n = int(math.ceil(2 * h)) + 1
    i, j = np.meshgrid(np.arange(-n, n + 1), np.arange(-n, n + 1), indexing="ij")
    x, y = i.ravel().astype(float), j.ravel().astype(float)
    r = np.hypot(x, y)
    alpha = 7.0 / (4.0 * math.pi * h * h)
    w = alpha * (1 - r / (2 * h)) ** 4 * (1 + 2 * r / h)
    sum_w = float(np.sum(np.where(r < 2 * h, w, 0.0)))
    k = (r > 0) & (r < 2 * h)
    x, y, r = x[k], y[k], r[k]
    q = r / h
    dw = alpha / h * (-5.0 * q * (1 - q / 2) ** 3)
    ex, ey = x / r, y / r
    return {"h_over_dp": h_over_dp, "sum_W": sum_w, "m2": float(np.sum(r * dw * ex * ex)),
            "m4_1111": float(np.sum(r * dw * ex ** 4)),
            "m4_1122": float(np.sum(r * dw * ex * ex * ey * ey)),
            "continuum": {"sum_W": 1.0, "m2": -1.0, "m4_1111": -0.75, "m4_1122": -0.25}}


def lattice_laws(nu, mom_tl, mom_ul):
    """In-plane stiffness (C11, C12, C66) of the SPH bulk operators at small strain on the lattice
    (see README.md): name -> (cmat, what)."""
    k = E_MOD / (3.0 * (1.0 - 2.0 * nu))
    g = E_MOD / (2.0 * (1.0 + nu))
    a = -mom_tl["m2"]
    b = mom_ul["m2"] ** 2
    z = UL_ENOG_ZETA
    kh, gh = a * k, a * TL_HF_ZETA * g
    return {
        "tl-hf": ((kh + gh, kh - gh, gh),
                  "d = 2 split with K' = -m2 K, G' = -m2 zeta G (h = 1.15 dp, zeta = 1.07): "
                  "eq 20 without B and the zeta-scaled Laplacian of eq 27"),
        "ul-og": ((b * (k + g), b * (k - g), b * g),
                  "d = 2 split scaled by m2^2 (h = 1.3 dp): continuity, pressure gradient, "
                  "velocity gradient without B (default) and shear divergence each carry -m2; "
                  "ul-oas the same plus its artificial stress (not modelled)"),
        "ul-enog": ((b * k - z * g * mom_ul["m4_1111"], b * k - z * g * mom_ul["m4_1122"],
                     -z * g * mom_ul["m4_1122"]),
                    "pressure m2^2 K plus the central-pair (conservative) Laplacian of eq 19 "
                    "with zeta = 3.5: C_abcd = -zeta G sum r W' e_a e_b e_c e_d (cubic on the "
                    "lattice, h = 1.3 dp)"),
        "ul-enog-integral": ((k + 0.75 * z * g, k + 0.25 * z * g, 0.25 * z * g),
                             "the same with the continuum (integral) moments: "
                             "lambda = K + zeta G/4, mu = zeta G/4"),
    }


# ----------------------------------------------------------------------------- main
def study(clamp, H, law, nu, levels, log):
    per, infos, modes = [], [], []
    cmat = stiffness_matrix(*law_constants(law, nu))
    for lev in levels:
        vals, info, mode = eigen(clamp, H, lev, cmat)
        per.append(period(vals[0]))
        infos.append(info)
        modes.append(mode)
    st = C.richardson(per)
    # omega^2 converges like T; its order is reported too (the eigenvalue error is the
    # quantity the FE theory predicts)
    om2 = [(2.0 * math.pi / t) ** 2 for t in per]
    st_om2 = C.richardson(om2)
    log(f"  {law:8s} {clamp:5s} H={H:g} nu={nu:g}: T {C.fmt(st)} s, order "
        f"{st['order'] if st['order'] is None else round(st['order'], 2)}, "
        f"dofs {[i['dofs'] for i in infos]}, {sum(i['seconds'] for i in infos):.1f} s")
    return per, st, st_om2, infos, modes


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true",
                    help="levels 0-2, nu = 0.4, H = 0.02 only, no JSON (smoke test)")
    ap.add_argument("--out", default=os.path.join(C.RESULTS, "fem-plate-modes.json"))
    a = ap.parse_args()
    log = C.logger()
    clock = C.Clock()
    levels_of = {c: (0, 1, 2) for c in CLAMPS} if a.quick else LEVELS
    nus = (0.4,) if a.quick else NUS
    hs = (0.02,) if a.quick else THICKNESSES
    cmd = C.command_line()
    kl = kl_root()

    entries, runs = [], []
    table = {}
    for H in hs:
        for nu in nus:
            for law in LAWS:
                lam, mu = law_constants(law, nu)
                e_bend, nu2d = bending_modulus(lam, mu)
                for clamp in CLAMPS:
                    levels = levels_of[clamp]
                    per, st, st_om2, infos, modes = study(clamp, H, law, nu, levels, log)
                    table[(H, nu, law, clamp)] = (per, st)
                    for i, md in zip(infos, modes):
                        runs.append({"law": law, "clamp": clamp, "H": H, "nu": nu, **i,
                                     "mode_1": md})
                    entries.append({
                        "params": {"law": law, "clamp": clamp, "L": L, "H": H,
                                   "base_length": SL if clamp == "frame" else None,
                                   "E": E_MOD, "nu": nu, "rho0": RHO, "lambda": lam,
                                   "mu": mu, "bending_modulus": e_bend,
                                   "in_plane_poisson_ratio": nu2d},
                        "levels": list(levels), "dofs": [i["dofs"] for i in infos],
                        "period": {"per_mesh": per, **st},
                        "omega1_squared": {"per_mesh": [(2 * math.pi / t) ** 2 for t in per],
                                           **st_om2},
                        "period_best": st["extrapolated"] if st["extrapolated"] is not None
                        else st["finest"],
                        "period_extrapolated_order_1": per[-1] + (per[-1] - per[-2]),
                        "command": cmd})

    # ------------------------------------------------------------------ checks
    checks = {}
    # beam theory against the solid clamp (the code's "T theory": TL eq 37, kL = 1.875,
    # E' = E/(1 - nu^2), oscillating_plate_2d.rs thin_plate_period)
    beam = []
    for H in hs:
        for nu in nus:
            for law in LAWS:
                lam, mu = law_constants(law, nu)
                e_bend, nu2d = bending_modulus(lam, mu)
                t_fe = _best(table[(H, nu, law, "solid")][1])
                t_code = euler_bernoulli_period(H, E_MOD / (1 - nu * nu), KL_CODE)
                t_eb = euler_bernoulli_period(H, e_bend, kl)
                t_tim = 2 * math.pi / timoshenko_omega(H, e_bend, mu, 5.0 / 6.0)
                t_tim_c = 2 * math.pi / timoshenko_omega(H, e_bend, mu, cowper_kappa(nu2d))
                t_shear_only = 2 * math.pi / timoshenko_omega(H, e_bend, mu, 5.0 / 6.0,
                                                              rotary=False)
                beam.append({"H": H, "nu": nu, "law": law, "T_fe_solid": t_fe,
                             "T_theory_code": t_code, "T_euler_bernoulli": t_eb,
                             "T_timoshenko_kappa_5_6": t_tim,
                             "T_timoshenko_cowper": t_tim_c,
                             "cowper_kappa": cowper_kappa(nu2d),
                             "T_timoshenko_no_rotary_inertia": t_shear_only,
                             "fe_vs_theory_code": t_fe / t_code - 1.0,
                             "fe_vs_euler_bernoulli": t_fe / t_eb - 1.0,
                             "fe_vs_timoshenko_kappa_5_6": t_fe / t_tim - 1.0,
                             "fe_vs_timoshenko_cowper": t_fe / t_tim_c - 1.0})
                b = beam[-1]
                log(f"beam theory {law:8s} H={H:g} nu={nu:g}: FE solid {t_fe:.6f}, code theory "
                    f"{t_code:.6f} ({b['fe_vs_theory_code']:+.3%}), EB {t_eb:.6f} "
                    f"({b['fe_vs_euler_bernoulli']:+.3%}), Timoshenko {t_tim:.6f} "
                    f"({b['fe_vs_timoshenko_kappa_5_6']:+.3%}), Cowper {t_tim_c:.6f} "
                    f"({b['fe_vs_timoshenko_cowper']:+.3%})")
    longer = all(b["fe_vs_euler_bernoulli"] > 0 for b in beam)
    not_longer = [{"H": b["H"], "nu": b["nu"], "law": b["law"],
                   "fe_vs_euler_bernoulli": b["fe_vs_euler_bernoulli"]}
                  for b in beam if not b["fe_vs_euler_bernoulli"] > 0]
    checks["beam_theory"] = {
        "what": "solid clamp against beam theory with the law's in-plane modulus "
                "E' = 4 mu (lam + mu)/(lam + 2 mu) (E/(1 - nu^2) for Hooke): the code's T theory "
                "(kL = 1.875, E' = E/(1 - nu^2) for every law), Euler-Bernoulli with the exact "
                "kL root, Timoshenko (shear and rotary inertia; kappa = 5/6 and Cowper's "
                "10 (1 + nu')/(12 + 11 nu') with the in-plane nu'). Expected: the FE period "
                "exceeds Euler-Bernoulli (shear deformation and rotary inertia); recorded, not "
                "asserted: the clamped face (u = 0, so eps_yy = 0 at the root) stiffens the "
                "root against beam theory's clamp by an amount that grows with nu (see "
                "timoshenko_nu0) and decays more slowly with H/L than the shear correction",
        "kl_root": kl, "kl_code": KL_CODE, "fe_longer_than_euler_bernoulli_everywhere": longer,
        "not_longer": not_longer, "rows": beam}
    # nu = 0 (Hooke): no Poisson coupling, so the clamped face's u_y = 0 (eps_yy = 0) does not
    # stiffen the root; the 2D plate should then agree with Timoshenko closely
    per0, st0, _, _, _ = study("solid", 0.02, "hooke", 0.0, levels_of["solid"], log)
    lam0, mu0 = law_constants("hooke", 0.0)
    t_tim0 = 2 * math.pi / timoshenko_omega(0.02, bending_modulus(lam0, mu0)[0], mu0, 5 / 6)
    checks["timoshenko_nu0"] = {
        "what": "solid clamp, Hooke, nu = 0, H = 0.02: FE (extrapolated) vs Timoshenko "
                "(kappa = 5/6); with nu > 0 the FE root is stiffer than Timoshenko's clamp "
                "(u = 0 on the whole face also holds eps_yy = 0 there), see beam_theory",
        "per_mesh": per0, "T_fe": _best(st0), "order": st0["order"],
        "T_timoshenko_kappa_5_6": t_tim0, "fe_vs_timoshenko": _best(st0) / t_tim0 - 1.0}
    log(f"nu = 0: FE {_best(st0):.6f} vs Timoshenko {t_tim0:.6f} "
        f"({_best(st0) / t_tim0 - 1.0:+.3%})")
    # the Timoshenko solver itself: stiff shear and no rotary inertia -> Euler-Bernoulli
    lam, mu = law_constants("hooke", 0.4)
    e_bend, _ = bending_modulus(lam, mu)
    t_lim = 2 * math.pi / timoshenko_omega(0.02, e_bend, mu * 1e3, 5.0 / 6.0, rotary=False)
    t_eb = euler_bernoulli_period(0.02, e_bend, kl)
    checks["timoshenko_limit"] = {"what": "Timoshenko with G x 1e3 and no rotary inertia vs "
                                          "Euler-Bernoulli (H = 0.02, nu = 0.4, Hooke)",
                                  "T_timoshenko": t_lim, "T_euler_bernoulli": t_eb,
                                  "relative_difference": t_lim / t_eb - 1.0}
    log(f"Timoshenko limit check: {t_lim / t_eb - 1.0:+.2e}")
    assert abs(t_lim / t_eb - 1.0) < 1e-4, "Timoshenko solver does not reach Euler-Bernoulli"

    # half model (antisymmetry) against the full model
    sym = []
    lev = 1 if a.quick else 2
    for clamp in CLAMPS:
        for law in LAWS:
            cmat = stiffness_matrix(*law_constants(law, 0.4))
            vh, ih, _ = eigen(clamp, 0.02, lev, cmat)
            vf, inf, mf = eigen(clamp, 0.02, lev, cmat, full=True, k=2)
            sym.append({"clamp": clamp, "law": law, "H": 0.02, "nu": 0.4, "level": lev,
                        "T_half": period(vh[0]), "T_full": period(vf[0]),
                        "T_full_mode_2": period(vf[1]),
                        "relative_difference": period(vh[0]) / period(vf[0]) - 1.0,
                        "full_mode_1": mf, "dofs_half": ih["dofs"], "dofs_full": inf["dofs"]})
            log(f"half vs full model {clamp} {law}: {sym[-1]['relative_difference']:+.2e} "
                f"(full model's second mode T = {sym[-1]['T_full_mode_2']:.5f} s)")
    sym_ok = max(abs(s["relative_difference"]) for s in sym) < 1e-8
    checks["symmetry"] = {"what": "lowest eigenvalue of the half model (u_x = 0 on y = 0) vs the "
                                  "full model's lowest (which must be the same bending mode)",
                          "tolerance": 1e-8, "passed": sym_ok, "rows": sym}
    assert sym_ok, "half model differs from the full model"

    # the first mode is the bending mode: tip moves vertically
    bend_ok = all(abs(r["mode_1"]["tip_uy"]) > 0.99 * r["mode_1"]["max_abs_uy"] for r in runs)
    checks["first_mode_is_bending"] = {
        "what": "for every run, |u_y| of the first mode at the tip (L, 0) is the largest |u_y| "
                "of the mode (to 1 %); end_max_abs_ux / tip_uy is recorded per run",
        "passed": bend_ok}
    assert bend_ok, "first mode is not the bending mode"

    # the SPH initial velocity (EB mode shape on x > 0, zero in the base) against FE mode 1
    proj = []
    for clamp in CLAMPS:
        for law in LAWS:
            for nu in sorted({min(nus), max(nus)}):
                r = initial_velocity_projection(clamp, 0.02, 2, stiffness_matrix(
                    *law_constants(law, nu)))
                proj.append({"law": law, "nu": nu, **r})
                log(f"initial velocity {clamp} {law} nu={nu:g}: kinetic energy in mode 1 "
                    f"{r['kinetic_energy_fraction_mode_1']:.5f}, tip velocity share "
                    f"{r['tip_velocity_fraction_mode_1']:.5f}")
    checks["initial_velocity_in_mode_1"] = {
        "what": "the SPH runs' initial velocity v_y = v_tip f(x)/f(L) (x > 0; TL eq 35 with "
                "kL = 1.875), projected (mass-weighted) on the FE mode 1 (level 2): the rest "
                "excites higher modes (the full model's second bending mode has T ~ 0.043 s), "
                "which perturb the zero crossings the SPH period is measured from",
        "rows": proj}

    # mesh convergence: observed orders
    orders = [{"law": e["params"]["law"], "clamp": e["params"]["clamp"],
               "H": e["params"]["H"], "nu": e["params"]["nu"],
               "order_T": e["period"]["order"], "order_omega2": e["omega1_squared"]["order"],
               "monotone": e["period"]["monotone"],
               "relative_error_estimate": (e["period"]["error_estimate"] / e["period_best"]
                                           if e["period"]["error_estimate"] is not None
                                           else None)}
              for e in entries]
    oks = [o["order_T"] for o in orders if o["order_T"] is not None]
    checks["mesh_convergence"] = {
        "what": "observed order p of the period (Richardson on the three finest meshes, "
                "common.richardson); P2 eigenvalues of a smooth problem converge at about "
                "h^4, the clamp corners (solid: clamped-free corners of 90 degrees; frame: the "
                "change from bonded to free on the faces y = +-H/2 at x = 0) lower it",
        "order_min": min(oks) if oks else None, "order_max": max(oks) if oks else None,
        "all_monotone": all(o["monotone"] for o in orders), "rows": orders}

    # frame / solid
    ratios = []
    for H in hs:
        for nu in nus:
            for law in LAWS:
                pf, sf = table[(H, nu, law, "frame")]
                ps, ss = table[(H, nu, law, "solid")]
                per_mesh = [f / s - 1.0 for f, s in zip(pf, ps)]  # common levels
                st = C.richardson(per_mesh)
                ratios.append({"H": H, "nu": nu, "law": law,
                               "frame_over_solid_minus_1": _best(sf) / _best(ss) - 1.0,
                               "per_mesh": per_mesh, **{"ratio_" + k: v for k, v in st.items()}})
                log(f"frame/solid - 1 {law:8s} H={H:g} nu={nu:g}: "
                    f"{ratios[-1]['frame_over_solid_minus_1']:+.4%}")
    checks["frame_over_solid"] = {
        "what": "T_frame / T_solid - 1 from the extrapolated (else finest) periods; per_mesh "
                "(the levels both clamps ran) and its own Richardson study",
        "rows": ratios}

    # d2-split vs Hooke
    lawr = []
    for H in hs:
        for nu in nus:
            for clamp in CLAMPS:
                t2 = _best(table[(H, nu, "d2-split", clamp)][1])
                th = _best(table[(H, nu, "hooke", clamp)][1])
                lam, mu = law_constants("hooke", nu)
                l2, m2 = law_constants("d2-split", nu)
                eb_ratio = math.sqrt(bending_modulus(lam, mu)[0] / bending_modulus(l2, m2)[0])
                lawr.append({"H": H, "nu": nu, "clamp": clamp,
                             "d2_over_hooke_minus_1": t2 / th - 1.0,
                             "beam_theory_sqrt_modulus_ratio_minus_1": eb_ratio - 1.0})
    checks["law_ratio"] = {"what": "T(d2-split) / T(hooke) - 1, and the beam-theory estimate "
                                   "sqrt(E'_hooke / E'_d2) - 1", "rows": lawr}

    # SPH lattice limit (informative)
    mom_tl, mom_ul = lattice_moments(TL_H_OVER_DP), lattice_moments(UL_H_OVER_DP)
    lev_lat = min(LATTICE_LEVEL, 2 if a.quick else LATTICE_LEVEL)
    idx = lev_lat  # levels start at 0
    lat_rows = []
    for H in hs:
        for nu in nus:
            laws = lattice_laws(nu, mom_tl, mom_ul)
            c_d2 = stiffness_matrix(*law_constants("d2-split", nu))
            for clamp in CLAMPS:
                per_d2, st_d2 = table[(H, nu, "d2-split", clamp)]
                for name, (cmat, _) in laws.items():
                    vals, _, _ = eigen(clamp, H, lev_lat, cmat)
                    ratio = period(vals[0]) / per_d2[idx]
                    lat_rows.append({
                        "method": name, "H": H, "nu": nu, "clamp": clamp,
                        "C11": cmat[0], "C12": cmat[1], "C66": cmat[2],
                        "T_over_T_d2_split": ratio,
                        "T_estimate": ratio * _best(st_d2),
                        "beam_estimate_T_over_T_d2_split":
                            math.sqrt(bending_modulus_c(c_d2) / bending_modulus_c(cmat))})
                log(f"lattice limit H={H:g} nu={nu:g} {clamp}: " + ", ".join(
                    f"{r['method']} {r['T_over_T_d2_split'] - 1:+.2%}" for r in lat_rows[-4:]))
    sph_lattice = {
        "what": "informative: the SPH methods' bulk operators at small strain on the undisturbed "
                "square lattice at their fixed h/dp (dp -> 0 at fixed h/dp, boundaries not "
                "analysed), as in-plane stiffness (C11, C12, C66); FE period ratio to the d2-split "
                f"law on level {lev_lat} (same mesh), times the extrapolated d2-split period. "
                "tl and tl-gm: B makes eq 20 exact on the lattice, so plane-strain Hooke "
                "(the GM penalty vanishes for smooth fields as dp -> 0)",
        "moments_tl": mom_tl, "moments_ul": mom_ul,
        "zeta_tl_hf": TL_HF_ZETA, "zeta_ul_enog": UL_ENOG_ZETA,
        "laws": {n: w for n, (_, w) in lattice_laws(0.4, mom_tl, mom_ul).items()},
        "level": lev_lat, "rows": lat_rows}

    out = {"case": "oscillating-plate-2d: first bending eigenfrequency, linear plane-strain FEM "
                   "reference (v_f -> 0 limit)",
           "schema": "validation/fem/README.md#oscillating-plate-plate_modespy",
           "command": cmd, "environment": C.environment(),
           "geometry": {"L": L, "thicknesses": list(hs), "base_length": SL,
                        "clamps": {"solid": "domain [0, L] x [-H/2, H/2], u = 0 on x = 0",
                                   "frame": "domain [-SL, L] x [-H/2, H/2], u = 0 on "
                                            "y = +-H/2 for -SL <= x <= 0 and on x = -SL"}},
           "material": {"E": E_MOD, "rho0": RHO, "nus": list(nus),
                        "laws": {"hooke": "plane-strain Hooke, lambda = E nu/((1+nu)(1-2nu)), "
                                          "mu = E/(2(1+nu))",
                                 "d2-split": "sigma = K tr(eps) I + 2G (eps - tr(eps)/2 I), "
                                             "K = E/(3(1-2nu)), G = mu: lambda_eff = K - G"}},
           "formulation": {"element": "P2 (6-node triangle), small-strain linear elasticity, "
                                      "consistent mass; degree-4 quadrature",
                           "eigen": "lowest eigenpair of K phi = omega^2 M phi on the free "
                                    "dofs, ARPACK shift-invert (sigma = 0)",
                           "model": "half model 0 <= y <= H/2 with u_x = 0 on y = 0 (bending "
                                    "modes are antisymmetric), checked against the full model",
                           "amplitude": "linear: the v_f -> 0 limit of the SPH runs (v_f = "
                                        "0.01...0.15); large amplitude not modelled"},
           "mesh_study": {"levels": {c: list(v) for c, v in levels_of.items()},
                          "refinement_ratio": 2,
                          "base": f"tensor grid: {NY_HALF} cells over [0, H/2] graded "
                                  f"{GRADING_Y:g}:1 toward y = H/2; {NX_FREE} cells on [0, L] "
                                  f"(and {NX_BASE} on [-SL, 0] for the frame) graded "
                                  f"{GRADING_X:g} (0.02 m / H):1 toward x = 0; each level "
                                  "splits every triangle into four (the diagonals point away "
                                  "from y = 0)"},
           "checks": checks, "sph_lattice_limit": sph_lattice, "entries": entries,
           "runs": runs, "total_seconds": clock()}
    if a.quick:
        log(f"quick run done in {clock():.0f} s (no JSON written)")
        return
    C.write_json(a.out, out)
    log(f"wrote {os.path.relpath(a.out)} in {clock():.0f} s")


def _best(st):
    return st["extrapolated"] if st["extrapolated"] is not None else st["finest"]


if __name__ == "__main__":
    sys.exit(main())
