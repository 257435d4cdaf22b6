"""Shared finite-element machinery of the plane-strain rubber references (punching, pulling).

Total Lagrangian, plane strain, compressible neo-Hookean (the SPH code's law):
    psi = mu/2 (I1 - 3) - mu ln J + lam/2 (ln J)^2,  I1 = C11 + C22 + 1,  J = det F (2x2),
    P = mu F + (lam ln J - mu) F^-T   (= F S with S = mu I + (lam ln J - mu) C^-1).
Elements: quadratic triangles (P2, 6 nodes, displacement only), scikit-fem for the mesh, the
basis and the degree-of-freedom numbering; the element kernels below are vectorised numpy over
all elements and quadrature points (the reference configuration never changes, so shape-function
gradients are evaluated once).

Contact: rigid, frictionless, axis-aligned boxes (the punches). Their signed-distance function g
(negative inside) is evaluated at the P2 nodes of the deformable body's boundary facets
(node-to-rigid-surface; each node carries its Simpson share w of the reference boundary length);
the normal pressure per reference length is
    p = max(0, pbar - eps g),  eps = kappa E / h_facet,  nodal force p w grad g,
with Uzawa augmented-Lagrangian updates pbar <- p until the largest penetration is below a
tolerance, so the converged answer does not depend on the penalty (checked in punching.py).
Everything is in SI units, forces per unit depth (N/m).
"""
from __future__ import annotations

import json
import math
import os
import platform
import sys
import time

import numpy as np
import scipy
import scipy.sparse as sp
import scipy.sparse.linalg as spla
import skfem
from skfem import Basis, ElementTriP2, ElementVector, FacetBasis, MeshTri

# ----------------------------------------------------------------------------- material
E_MOD = 1.0e9
NU = 0.45
MU = E_MOD / (2.0 * (1.0 + NU))
LAM = NU * E_MOD / ((1.0 + NU) * (1.0 - 2.0 * NU))
# the volumetric part -mu ln J + lam/2 (ln J)^2 is convex in J only for ln J < 1 + mu/lam:
# beyond J = 3.03 (nu = 0.45) the model itself loses stability (local runaway expansion)
J_CONVEXITY_LIMIT = math.exp(1.0 + MU / LAM)


def homogeneous_plane_strain(lam_y: float, mu: float = MU, lam: float = LAM):
    """Plane-strain neo-Hookean between frictionless platens: lambda_z = 1, lambda_y given,
    lambda_x from sigma_xx = 0: mu (lx^2 - 1) + lam ln(lx ly) = 0 (Newton, monotone in lx).
    Returns (lambda_x, P_yy)."""
    lx = 1.0
    for _ in range(100):
        f = mu * (lx * lx - 1.0) + lam * math.log(lx * lam_y)
        df = 2.0 * mu * lx + lam / lx
        step = f / df
        lx -= step
        if abs(step) < 1e-16 * lx:
            break
    pyy = (mu * (lam_y * lam_y - 1.0) + lam * math.log(lx * lam_y)) / lam_y
    return lx, pyy


def stress_and_tangent(F, mu=MU, lam=LAM, need_tangent=True):
    """F: (2,2,...) deformation gradients. Returns (P, A, J) with P (2,2,...),
    A_iJkL = dP_iJ/dF_kL (2,2,2,2,...) and J (...)."""
    J = F[0, 0] * F[1, 1] - F[0, 1] * F[1, 0]
    if np.any(J <= 0.0):
        raise FloatingPointError("J <= 0 at a quadrature point")
    Fit = np.empty_like(F)  # F^-T
    Fit[0, 0] = F[1, 1] / J
    Fit[0, 1] = -F[1, 0] / J
    Fit[1, 0] = -F[0, 1] / J
    Fit[1, 1] = F[0, 0] / J
    lnJ = np.log(J)
    c = lam * lnJ - mu
    P = mu * F + c * Fit
    if not need_tangent:
        return P, None, J
    eye = np.eye(2)
    A = (mu * np.einsum("ik,jl->ijkl", eye, eye)[(...,) + (None,) * (F.ndim - 2)]
         + lam * np.einsum("ij...,kl...->ijkl...", Fit, Fit)
         - c * np.einsum("il...,kj...->ijkl...", Fit, Fit))
    return P, A, J


# ----------------------------------------------------------------------------- mesh
def graded_half(length: float, n: int, ratio: float) -> np.ndarray:
    """n+1 points on [0, length], spacing shrinking geometrically (largest/smallest = ratio) toward
    `length`. Doubling n nests the points (refinement ratio exactly 2)."""
    s = np.linspace(0.0, 1.0, n + 1)
    if ratio == 1.0:
        return length * s
    beta = math.log(ratio)
    # spacing ~ exp(-beta s): x(s) = (1 - exp(-beta s)) / (1 - exp(-beta))
    x = (1.0 - np.exp(-beta * s)) / (1.0 - math.exp(-beta))
    x[-1] = 1.0
    return length * x


def symmetric_mesh(half_w, half_h, nx, ny, ratio_x, ratio_y, quarter):
    """Triangulated tensor grid of [-half_w, half_w] x [-half_h, half_h] (or the quarter
    [0, half_w] x [0, half_h]) graded toward the edges x = +-half_w and y = +-half_h. Every
    rectangle is cut along the diagonal that points away from the centre, so the full mesh is
    mirror-symmetric about both axes and the quarter mesh is exactly its restriction."""
    xh = graded_half(half_w, nx, ratio_x)
    yh = graded_half(half_h, ny, ratio_y)
    xs = xh if quarter else np.concatenate([-xh[:0:-1], xh])
    ys = yh if quarter else np.concatenate([-yh[:0:-1], yh])
    X, Y = np.meshgrid(xs, ys, indexing="ij")
    p = np.vstack([X.ravel(), Y.ravel()])
    nxs, nys = len(xs), len(ys)
    idx = np.arange(nxs * nys).reshape(nxs, nys)
    i, j = np.meshgrid(np.arange(nxs - 1), np.arange(nys - 1), indexing="ij")
    i, j = i.ravel(), j.ravel()
    a, b, c, d = idx[i, j], idx[i + 1, j], idx[i + 1, j + 1], idx[i, j + 1]
    xc = 0.5 * (xs[i] + xs[i + 1])
    yc = 0.5 * (ys[j] + ys[j + 1])
    same = xc * yc > 0  # diagonal a-c (lower-left to upper-right) in quadrants 1 and 3
    t1 = np.where(same, np.vstack([a, b, c]), np.vstack([a, b, d]))
    t2 = np.where(same, np.vstack([a, c, d]), np.vstack([b, c, d]))
    t = np.hstack([t1, t2])
    return MeshTri(p, t)


def tensor_quarter(xs, ys):
    """Quarter mesh on the tensor grid xs x ys (both starting at 0), every rectangle cut along
    its diagonal pointing away from the origin (as symmetric_mesh does in the first quadrant)."""
    X, Y = np.meshgrid(xs, ys, indexing="ij")
    p = np.vstack([X.ravel(), Y.ravel()])
    idx = np.arange(len(xs) * len(ys)).reshape(len(xs), len(ys))
    i, j = np.meshgrid(np.arange(len(xs) - 1), np.arange(len(ys) - 1), indexing="ij")
    i, j = i.ravel(), j.ravel()
    a, b, c, d = idx[i, j], idx[i + 1, j], idx[i + 1, j + 1], idx[i, j + 1]
    return MeshTri(p, np.hstack([np.vstack([a, b, c]), np.vstack([a, c, d])]))


def refine_where(mesh, pred, times=1):
    """Conforming local refinement (scikit-fem's red-green-blue) of the triangles whose centroid
    satisfies pred(x, y), repeated `times` times."""
    for _ in range(times):
        c = mesh.p[:, mesh.t].mean(axis=1)
        marked = np.nonzero(pred(c[0], c[1]))[0]
        if len(marked) == 0:
            break
        mesh = mesh.refined(marked)
    return mesh


def mirror_full(quarter: MeshTri) -> MeshTri:
    """Full mesh from a quarter mesh on x >= 0, y >= 0 by reflection about both axes (nodes on
    the axes are merged), so the full mesh is exactly mirror-symmetric."""
    p, t = quarter.p, quarter.t
    pts, tris = [], []
    offset = 0
    for sx, sy in ((1, 1), (-1, 1), (-1, -1), (1, -1)):
        q = p * np.array([[sx], [sy]])
        tt = t.copy()
        if sx * sy < 0:
            tt = tt[[0, 2, 1]]  # keep counter-clockwise orientation
        pts.append(q)
        tris.append(tt + offset)
        offset += p.shape[1]
    P = np.hstack(pts)
    T = np.hstack(tris)
    key = np.round(P / (np.abs(P).max() * 1e-12)).astype(np.int64)
    _, first, inv = np.unique(key, axis=1, return_index=True, return_inverse=True)
    inv = inv.ravel()
    return MeshTri(np.ascontiguousarray(P[:, first]), np.ascontiguousarray(inv[T]))


# ----------------------------------------------------------------------------- rigid box
class RigidBox:
    """Axis-aligned rigid box (centre cx, cy; half sizes a, b), frictionless, its corners
    rounded with radius r (r = 0: sharp). Rounding makes the signed distance continuously
    differentiable for penetrations smaller than r, so a surface node can slide around a corner
    without the nearest face flipping under it."""

    def __init__(self, cx, cy, a, b, name, r=0.0):
        self.cx, self.cy, self.a, self.b, self.name, self.r = cx, cy, a, b, name, r

    def sdf(self, x, y):
        """Signed distance g (negative inside), its gradient n (2, ...) and the Hessian
        (2, 2, ...) (non-zero only in the corner regions)."""
        g, n, H = self._sdf_sharp(x, y, self.a - self.r, self.b - self.r)
        return g - self.r, n, H

    def _sdf_sharp(self, x, y, a, b):
        dx, dy = x - self.cx, y - self.cy
        sx, sy = np.where(dx >= 0, 1.0, -1.0), np.where(dy >= 0, 1.0, -1.0)
        qx, qy = np.abs(dx) - a, np.abs(dy) - b
        g = np.empty_like(x)
        n = np.zeros((2,) + x.shape)
        H = np.zeros((2, 2) + x.shape)
        corner = (qx > 0) & (qy > 0)
        side_x = (qx > 0) & (qy <= 0)
        side_y = (qy > 0) & (qx <= 0)
        inside = (qx <= 0) & (qy <= 0)
        r = np.hypot(qx[corner], qy[corner])
        g[corner] = r
        nx_, ny_ = sx[corner] * qx[corner] / r, sy[corner] * qy[corner] / r
        n[0][corner], n[1][corner] = nx_, ny_
        H[0, 0][corner] = (1 - nx_ * nx_) / r
        H[0, 1][corner] = -nx_ * ny_ / r
        H[1, 0][corner] = -nx_ * ny_ / r
        H[1, 1][corner] = (1 - ny_ * ny_) / r
        g[side_x] = qx[side_x]
        n[0][side_x] = sx[side_x]
        g[side_y] = qy[side_y]
        n[1][side_y] = sy[side_y]
        ix = inside & (qx > qy)
        iy = inside & ~(qx > qy)
        g[ix] = qx[ix]
        n[0][ix] = sx[ix]
        g[iy] = qy[iy]
        n[1][iy] = sy[iy]
        return g, n, H


# ----------------------------------------------------------------------------- solver
class NewtonFailure(RuntimeError):
    pass


def sparse_solve(A, b):
    """Direct solve of a (structurally) symmetric system: SuperLU with a minimum-degree
    ordering of A^T + A and diagonal pivoting preferred."""
    lu = spla.splu(A.tocsc(), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.1,
                   options={"SymmetricMode": True})
    x = lu.solve(b)
    if not np.all(np.isfinite(x)):
        raise RuntimeError("singular matrix")
    return x


class Problem:
    """Quasi-static plane-strain hyperelastic body (P2) with Dirichlet dofs and rigid boxes."""

    def __init__(self, mesh: MeshTri, contact_facets=None, kappa=100.0, intorder=4,
                 length_scale=1e-3):
        self.mesh = mesh
        self.elem = ElementVector(ElementTriP2())
        self.basis = Basis(mesh, self.elem, intorder=intorder)
        b = self.basis
        self.N = b.N
        # shape-function gradients (ndof_loc, 2, 2, nel, nq) and weights (nel, nq)
        self.G = np.stack([b.basis[i][0].grad for i in range(len(b.basis))])
        self.dx = b.dx
        self.edofs = b.element_dofs  # (12, nel)
        nl = self.edofs.shape[0]
        self.rows = np.repeat(self.edofs[:, None, :], nl, axis=1).ravel()
        self.cols = np.repeat(self.edofs[None, :, :], nl, axis=0).ravel()
        # P2 "nodes": vertices then edge midpoints; their x and y dofs and reference positions
        self.node_dofs = np.hstack([b.nodal_dofs, b.facet_dofs])  # (2, nnodes)
        mid = mesh.p[:, mesh.facets].mean(axis=1)
        self.X = np.hstack([mesh.p, mid])
        self.L = length_scale
        self.h_min = self._hmin()
        self.fixed = np.zeros(0, dtype=np.int64)
        self.boxes: list[RigidBox] = []
        self.kappa = kappa
        self.contact = None
        if contact_facets is not None and len(contact_facets):
            # node-to-rigid contact: the P2 nodes of the contact facets, each with its share of
            # the reference boundary length (Simpson weights of a quadratic edge: h/6, 4h/6, h/6)
            f = np.asarray(contact_facets)
            nv = mesh.p.shape[1]
            hf = np.linalg.norm(mesh.p[:, mesh.facets[0, f]] - mesh.p[:, mesh.facets[1, f]], axis=0)
            w = np.zeros(self.X.shape[1])
            hn = np.zeros(self.X.shape[1])
            for ends in (mesh.facets[0, f], mesh.facets[1, f]):
                np.add.at(w, ends, hf / 6.0)
                np.maximum.at(hn, ends, hf)
            np.add.at(w, nv + f, 4.0 * hf / 6.0)
            hn[nv + f] = hf
            self.cnodes = np.nonzero(w)[0]
            self.cw = w[self.cnodes]
            self.ceps = kappa * E_MOD / hn[self.cnodes]
            self.cdofs = self.node_dofs[:, self.cnodes]  # (2, nc)
            self.cf = f
            self.pbar = None
        self.stats = {"newton_iterations": 0, "solves": 0, "assemblies": 0, "convexified": 0}

    def _hmin(self):
        p, f = self.mesh.p, self.mesh.facets
        return float(np.min(np.linalg.norm(p[:, f[0]] - p[:, f[1]], axis=0)))

    # --------------------------------------------------------------- boundary data
    def dofs_where(self, pred, comps=(0, 1)):
        """Dofs (components `comps`) of the P2 nodes whose reference position satisfies pred."""
        mask = pred(self.X[0], self.X[1])
        return np.concatenate([self.node_dofs[c][mask] for c in comps])

    def set_fixed(self, dofs):
        self.fixed = np.unique(np.asarray(dofs, dtype=np.int64))
        free = np.ones(self.N, dtype=bool)
        free[self.fixed] = False
        self.free = np.nonzero(free)[0]

    def set_boxes(self, boxes):
        self.boxes = boxes
        if self.contact is None and hasattr(self, "cnodes"):
            self.pbar = [np.zeros_like(self.cw) for _ in boxes]
            self.contact = True

    def get_multipliers(self):
        return [pb.copy() for pb in self.pbar] if self.contact else None

    def set_multipliers(self, m):
        if m is not None:
            self.pbar = [pb.copy() for pb in m]

    # --------------------------------------------------------------- kinematics
    def grad_u(self, u):
        ue = u[self.edofs]  # (12, nel)
        return np.einsum("iabeq,ie->abeq", self.G, ue)

    def deformation_gradient(self, u):
        F = self.grad_u(u)
        F[0, 0] += 1.0
        F[1, 1] += 1.0
        return F

    def contact_points(self, u):
        return self.X[:, self.cnodes] + u[self.cdofs]

    # --------------------------------------------------------------- assembly
    def assemble(self, u, need_tangent=True, convexify=False):
        """Residual r = f_int - f_contact (size N) and the tangent K (csr). convexify drops the
        contact curvature term -p w Hess(g) (negative semi-definite at a convex corner)."""
        self.stats["assemblies"] += 1
        F = self.deformation_gradient(u)
        P, A, J = stress_and_tangent(F, need_tangent=need_tangent)
        re = np.einsum("iabeq,abeq,eq->ie", self.G, P, self.dx)
        r = np.bincount(self.edofs.ravel(), weights=re.ravel(), minlength=self.N)
        K = None
        if need_tangent:
            AG = np.einsum("abcdeq,jcdeq->jabeq", A, self.G)
            Ke = np.einsum("iabeq,jabeq,eq->ije", self.G, AG, self.dx)
            K = sp.coo_matrix((Ke.ravel(), (self.rows, self.cols)), shape=(self.N, self.N))
        if self.contact:
            rc, Kc = self._contact(u, need_tangent, convexify)
            r -= rc
            if need_tangent:
                K = K + Kc
        if need_tangent:
            K = K.tocsr()
        return r, K

    def contact_state(self, u):
        """Per box: gap g, normal n, Hessian H, nominal pressure p at the contact nodes."""
        x = self.contact_points(u)
        out = []
        for box, pbar in zip(self.boxes, self.pbar):
            g, n, H = box.sdf(x[0], x[1])
            p = np.maximum(0.0, pbar - self.ceps * g)
            out.append((g, n, H, p))
        return out

    def _contact(self, u, need_tangent, convexify=False):
        """Force on the body p n w at each contact node and its tangent
        w (eps n n^T - p Hess g) where the node is active."""
        rc = np.zeros(self.N)
        data, rows, cols = [], [], []
        for g, n, H, p in self.contact_state(u):
            act = p > 0
            if not np.any(act):
                continue
            fw = n * (p * self.cw)
            np.add.at(rc, self.cdofs[0], fw[0])
            np.add.at(rc, self.cdofs[1], fw[1])
            if need_tangent:
                k = (self.ceps * self.cw * act) * np.einsum("a...,b...->ab...", n, n)
                if not convexify:
                    k = k - (p * self.cw) * H
                for a in range(2):
                    for b in range(2):
                        data.append(k[a, b][act])
                        rows.append(self.cdofs[a][act])
                        cols.append(self.cdofs[b][act])
        Kc = None
        if need_tangent:
            if data:
                Kc = sp.coo_matrix((np.concatenate(data), (np.concatenate(rows),
                                    np.concatenate(cols))), shape=(self.N, self.N))
            else:
                Kc = sp.coo_matrix((self.N, self.N))
        return rc, Kc

    def box_forces(self, u):
        """Force (fx, fy) that each box exerts on the body (per unit depth)."""
        return [np.sum(n * (p * self.cw), axis=1) for g, n, H, p in self.contact_state(u)]

    # --------------------------------------------------------------- Newton
    def energy(self, u):
        """Total potential energy per unit depth: strain energy + augmented-Lagrangian contact
        energy sum w (1/(2 eps)) max(0, pbar - eps g)^2 (its gradient is the residual);
        +inf where J <= 0."""
        F = self.deformation_gradient(u)
        J = F[0, 0] * F[1, 1] - F[0, 1] * F[1, 0]
        if np.any(J <= 0.0):
            return np.inf
        lnJ = np.log(J)
        psi = 0.5 * MU * (np.einsum("ab...,ab...->...", F, F) - 2.0) - MU * lnJ \
            + 0.5 * LAM * lnJ ** 2
        e = float(np.sum(psi * self.dx))
        if self.contact:
            for g, n, H, p in self.contact_state(u):
                e += float(np.sum(self.cw * p * p / (2.0 * self.ceps)))
        return e

    def _line_search(self, u, du, r_free):
        """Take the full Newton step when it lowers the energy (Armijo, c1 = 1e-4) or the
        residual norm; otherwise backtrack on the energy with quadratic interpolation. The
        equilibria sought are energy minima, so this keeps Newton on the stable branch and stops
        nodes that enter contact deeply (or J -> 0) from throwing the iteration away."""
        free = self.free
        e0 = self.energy(u)
        d0 = float(r_free @ du)  # directional derivative of the energy along du
        rn0 = np.linalg.norm(r_free)
        alpha = 1.0
        for k in range(30):
            trial = u.copy()
            trial[free] += alpha * du
            e1 = self.energy(trial)
            if np.isfinite(e1):
                if d0 < 0 and e1 <= e0 + 1e-4 * alpha * d0:
                    return trial, alpha
                if k == 0:
                    r1, _ = self.assemble(trial, need_tangent=False)
                    if np.linalg.norm(r1[free]) < rn0:
                        return trial, alpha
                if d0 < 0 and e1 > e0:
                    # minimiser of the quadratic through e0, d0 and e1
                    a_new = -d0 * alpha ** 2 / (2.0 * (e1 - e0 - d0 * alpha))
                    alpha = min(max(a_new, 0.1 * alpha), 0.5 * alpha)
                    continue
            alpha *= 0.5
        raise NewtonFailure("line search failed")

    def _solve(self, K, rhs):
        self.stats["solves"] += 1
        try:
            du = sparse_solve(K[self.free][:, self.free], rhs)
        except RuntimeError as exc:  # singular
            raise NewtonFailure(str(exc))
        if not np.all(np.isfinite(du)):
            raise NewtonFailure("non-finite increment")
        return du

    def _direction(self, u, K, r_free):
        """Newton direction. If it is not a descent direction of the energy (the tangent is
        indefinite), first drop the contact curvature term -p w Hess(g) (negative at a convex
        punch corner), then shift the tangent by beta M (M the mass matrix, beta growing tenfold)
        until it is: a Levenberg-Marquardt / pseudo-transient step, which, like the damping of a
        dynamic relaxation, leads to a stable equilibrium (an energy minimum)."""
        self.stats["newton_iterations"] += 1
        du = self._solve(K, -r_free)
        if float(r_free @ du) < 0.0:
            return du
        self.stats["convexified"] += 1
        if self.contact:
            _, K = self.assemble(u, convexify=True)
            du = self._solve(K, -r_free)
            if float(r_free @ du) < 0.0:
                return du
        M = self.mass_matrix()
        beta = 1e-4 * float(K.diagonal().mean() / M.diagonal().mean())
        for _ in range(10):
            du = self._solve(K + beta * M, -r_free)
            if float(r_free @ du) < 0.0:
                return du
            beta *= 10.0
        raise NewtonFailure("no descent direction")

    def negative_eigenvalues(self, u):
        """Number of negative eigenvalues of the tangent K_ff (free dofs), from the signs of the
        pivots of a symmetric-mode LU factorisation without pivoting off the diagonal (Sylvester's
        law of inertia). 0 means the equilibrium is stable."""
        _, K = self.assemble(u)
        Kff = K[self.free][:, self.free].tocsc()
        Kff = 0.5 * (Kff + Kff.T)
        lu = spla.splu(Kff.tocsc(), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                       options={"SymmetricMode": True})
        if not np.array_equal(lu.perm_r, lu.perm_c):
            raise RuntimeError("factorisation pivoted off the diagonal: inertia unknown")
        return int(np.sum(lu.U.diagonal() < 0))

    def newton(self, u, tol_rel=1e-6, maxit=12, lm_maxit=150):
        """Solve r_free(u) = 0 from u (fixed dofs already hold their prescribed values).
        Converged when |r_free| <= tol_rel E L (E L = 3e6 N/m: |r| <= 3 N/m against forces of
        1e5 - 1e7 N/m). Newton with an energy line search first; if that has not converged
        after maxit iterations (a contact node switching faces or status at a punch corner, a
        strongly sheared corner region), Levenberg-Marquardt iterations on the energy:
        (K_c + beta M) du = -r with K_c the convexified tangent, beta lowered after a step that
        lowers the energy as predicted and raised otherwise (a trust region, i.e. a damped
        pseudo-time relaxation that only stops at a stable equilibrium)."""
        tol_r = tol_rel * E_MOD * self.L
        free = self.free
        for it in range(maxit):
            try:
                r, K = self.assemble(u)
            except FloatingPointError as exc:
                raise NewtonFailure(str(exc))
            rn = np.linalg.norm(r[free])
            if not np.isfinite(rn):
                raise NewtonFailure("non-finite residual")
            if rn <= tol_r:
                return u, it
            try:
                du = self._direction(u, K, r[free])
                u_new, alpha = self._line_search(u, du, r[free])
            except NewtonFailure:
                break
            if alpha * np.max(np.abs(du)) > 0.25 * self.L:
                raise NewtonFailure("diverging increment")
            u = u_new
        return self._levenberg_marquardt(u, tol_r, lm_maxit, it)

    def _levenberg_marquardt(self, u, tol_r, maxit, it0):
        free = self.free
        self.stats["lm_calls"] = self.stats.get("lm_calls", 0) + 1
        M = self.mass_matrix()
        Mff = M[free][:, free]
        beta = None
        e0 = self.energy(u)
        for it in range(maxit):
            self.stats["lm_iterations"] = self.stats.get("lm_iterations", 0) + 1
            try:
                r, K = self.assemble(u, convexify=True)
            except FloatingPointError as exc:
                raise NewtonFailure(str(exc))
            rf = r[free]
            rn = np.linalg.norm(rf)
            if rn <= tol_r:
                return u, it0 + it
            Kff = K[free][:, free]
            if beta is None:
                beta = 1e-3 * float(Kff.diagonal().mean() / Mff.diagonal().mean())
            for _ in range(40):
                self.stats["solves"] += 1
                try:
                    du = sparse_solve(Kff + beta * Mff, -rf)
                except RuntimeError:
                    beta *= 4.0
                    continue
                trial = u.copy()
                trial[free] += du
                e1 = self.energy(trial)
                pred = float(rf @ du + 0.5 * du @ (Kff @ du))  # model decrease (< 0)
                if np.isfinite(e1) and pred < 0 and (e1 - e0) <= 0.1 * pred:
                    u, e0 = trial, e1
                    beta = max(beta / 3.0, 1e-12)
                    break
                if np.isfinite(e1) and abs(pred) < 1e-13 * abs(e0):
                    # decrease below the round-off of the energy: accept if the residual drops
                    r1, _ = self.assemble(trial, need_tangent=False)
                    if np.linalg.norm(r1[free]) < rn:
                        u, e0 = trial, e1
                        break
                beta *= 4.0
            else:
                raise NewtonFailure("Levenberg-Marquardt: no decrease")
        raise NewtonFailure(f"no convergence (|r| = {rn:.3e} N/m after Newton and "
                            f"{maxit} Levenberg-Marquardt iterations)")

    def max_penetration(self, u):
        """Largest |g| over the nodes that carry contact pressure (penetration, or a gap left
        under pressure) and the contact states."""
        worst = 0.0
        states = self.contact_state(u)
        for g, n, H, p in states:
            act = p > 0
            if np.any(act):
                worst = max(worst, float(np.max(np.abs(g[act]))))
        return worst, states

    def _augment(self, states):
        for k, (g, n, H, p) in enumerate(states):
            self.pbar[k] = p.copy()

    def solve_step(self, u, tol_pen, converge_contact, max_aug=40, accept_factor=20.0):
        """Newton, then Uzawa augmentation of the contact pressures pbar <- max(0, pbar - eps g).
        converge_contact=False (intermediate load steps): one augmentation, kept for the next
        step. True (reported states): repeat until the largest |g| under pressure is below
        tol_pen; a node at the edge of the contact zone can toggle in and out, so after max_aug
        sweeps a state within accept_factor * tol_pen is accepted (recorded in stats)."""
        iters = 0
        u, it = self.newton(u)
        iters += it
        if not self.contact:
            return u, iters, 0
        best = None
        for aug in range(max_aug if converge_contact else 1):
            worst, states = self.max_penetration(u)
            if worst <= tol_pen:
                return u, iters, aug
            if best is None or worst < best[0]:
                best = (worst, u.copy(), self.get_multipliers())
            self._augment(states)
            if not converge_contact:
                return u, iters, 1
            u, it = self.newton(u)
            iters += it
        if best[0] <= accept_factor * tol_pen:
            self.stats["contact_accepted_at"] = max(self.stats.get("contact_accepted_at", 0.0),
                                                     best[0])
            self.set_multipliers(best[2])
            return best[1], iters, max_aug
        raise NewtonFailure(f"augmented Lagrangian: penetration {worst:.3e} > {tol_pen:.3e}")

    # --------------------------------------------------------------- path following
    def follow(self, u, apply_load, targets, callback, dt0, dt_max, tol_pen=0.0,
               predictor=None, dt_min=1e-6, log=None, eig_check=None, t0=0.0):
        """Load stepping in the load parameter t from t0 to max(targets) with adaptive steps.

        apply_load(t, u): writes the prescribed dofs into u and moves the boxes.
        predictor(t, u) -> u: optional first guess for the first step (from t0).
        callback(t, u) is called at every target (exactly hit). Returns the last converged t.
        Steps that fail are halved; steps that converge quickly grow (x1.5, up to dt_max).
        eig_check(t, u): optional, called after every converged step."""
        t = t0
        targets = sorted(targets)
        u_prev, t_prev = None, None
        dt = dt0
        ti = 0
        while ti < len(targets):
            t_new = min(t + dt, targets[ti])
            if targets[ti] - t_new < 0.25 * dt:
                t_new = targets[ti]
            saved = (u.copy(), self.get_multipliers())
            # predictor: secant extrapolation along the path
            if u_prev is not None:
                guess = u + (t_new - t) / (t - t_prev) * (u - u_prev)
            elif predictor is not None:
                guess = predictor(t_new, u)
            else:
                guess = u.copy()
            apply_load(t_new, guess)
            try:
                self._check_admissible(guess)
            except NewtonFailure:
                guess = u.copy()
                apply_load(t_new, guess)
            try:
                unew, iters, aug = self.solve_step(guess, tol_pen, t_new == targets[ti])
            except NewtonFailure as exc:
                u = saved[0]
                self.set_multipliers(saved[1])
                dt *= 0.5
                if log:
                    log(f"    step to t={t_new:.6g} failed ({exc}); dt -> {dt:.3g}")
                if dt < dt_min:
                    return t, u
                continue
            u_prev, t_prev = u, t
            u, t = unew, t_new
            if eig_check is not None:
                eig_check(t, u)
            if iters <= 6:
                dt = min(dt * 1.5, dt_max)
            if t == targets[ti]:
                callback(t, u)
                ti += 1
        return t, u

    def _check_admissible(self, u):
        F = self.deformation_gradient(u)
        if np.min(F[0, 0] * F[1, 1] - F[0, 1] * F[1, 0]) <= 0.05:
            raise NewtonFailure("predictor not admissible")

    # --------------------------------------------------------------- post-processing
    def area_integral(self, u):
        F = self.deformation_gradient(u)
        J = F[0, 0] * F[1, 1] - F[0, 1] * F[1, 0]
        return float(np.sum(J * self.dx)), float(np.sum(self.dx))

    def reaction(self, u, dofs):
        r, _ = self.assemble(u, need_tangent=False)
        return float(np.sum(r[dofs]))

    def current_nodes(self, u):
        return self.X + u[self.node_dofs]

    def boundary_curve(self, u, facets, nsub=2):
        """Deformed positions along boundary facets: for each facet (in the order given),
        points at nsub+1 equally spaced reference parameters (P2 interpolation)."""
        m = self.mesh
        x = self.current_nodes(u)
        nv = m.p.shape[1]
        v0, v1 = m.facets[0, facets], m.facets[1, facets]
        mid = nv + facets
        s = np.linspace(0.0, 1.0, nsub + 1)
        N0 = (1 - s) * (1 - 2 * s)
        N1 = s * (2 * s - 1)
        Nm = 4 * s * (1 - s)
        pts = (x[:, v0, None] * N0 + x[:, v1, None] * N1 + x[:, mid, None] * Nm)
        return pts, v0, v1  # pts (2, nf, nsub+1)

    def boundary_chain(self, facets, start_pred):
        """Order boundary facets into a chain starting at the vertex satisfying start_pred.
        Returns (ordered facet indices, orientation flags: True if facet goes v0 -> v1)."""
        m = self.mesh
        f = np.asarray(facets)
        adj = {}
        for k, fi in enumerate(f):
            for v in m.facets[:, fi]:
                adj.setdefault(int(v), []).append(k)
        ends = [v for v, ks in adj.items() if len(ks) == 1]
        cand = [v for v in (ends if ends else list(adj)) if start_pred(*m.p[:, v])]
        v = cand[0]
        used = np.zeros(len(f), dtype=bool)
        order, fwd = [], []
        while True:
            nxt = [k for k in adj[v] if not used[k]]
            if not nxt:
                break
            k = nxt[0]
            used[k] = True
            a, b = m.facets[:, f[k]]
            order.append(f[k])
            fwd.append(int(a) == v)
            v = int(b) if int(a) == v else int(a)
        return np.array(order), np.array(fwd)

    def polyline(self, u, facets, start_pred, nsub=2):
        order, fwd = self.boundary_chain(facets, start_pred)
        pts, _, _ = self.boundary_curve(u, order, nsub)
        pts = np.where(fwd[None, :, None], pts, pts[:, :, ::-1])
        line = [pts[:, 0, 0]]
        for k in range(pts.shape[1]):
            for j in range(1, nsub + 1):
                line.append(pts[:, k, j])
        return np.array(line)  # (npts, 2)

    # --------------------------------------------------------------- stability
    def mass_matrix(self):
        if not hasattr(self, "_M"):
            phi = [self.basis.basis[i][0].value for i in range(len(self.basis.basis))]
            V = np.stack(phi)  # (12, 2, nel, nq)
            Me = np.einsum("iaeq,jaeq,eq->ije", V, V, self.dx)
            self._M = sp.coo_matrix((Me.ravel(), (self.rows, self.cols)),
                                    shape=(self.N, self.N)).tocsr()
        return self._M

    def lowest_eigenpairs(self, u, k=4):
        """Lowest eigenvalues of K_ff phi = omega M_ff phi (the tangent's stability measure,
        mesh-independent units Pa/m^2 per unit density-free mass). Negative => unstable."""
        _, K = self.assemble(u)
        f = self.free
        Kff = K[f][:, f].tocsc()
        Mff = self.mass_matrix()[f][:, f].tocsc()
        Kff = 0.5 * (Kff + Kff.T)
        shift = -1e-3 * E_MOD / self.L ** 2
        vals, vecs = spla.eigsh(Kff, k=k, M=Mff, sigma=shift, which="LM")
        o = np.argsort(vals)
        return vals[o], vecs[:, o]


# ----------------------------------------------------------------------------- mesh study
def richardson(values, ratio=2.0, safety=1.25):
    """values: sequence from coarse to fine (refinement ratio `ratio`). Uses the three finest.
    Monotone (successive differences of one sign, shrinking): observed order
    p = ln(d1/d2)/ln(ratio), extrapolated value f3 + d2/(r^p - 1), error estimate
    safety*|d2|/(r^p - 1) (the grid-convergence index of the finest mesh), with p limited to
    at most 4 for the extrapolation. An observed order below 1 is not an asymptotic range (the
    punching force at 20 % with r = 50 um corners gave 0.29: the meshes sampled the saw-tooth
    of nodes slipping round the corner, and the extrapolation moved the value by 6 %): then,
    as when not monotone, no extrapolation, and the error estimate is the largest change among
    the three finest meshes."""
    v = [x for x in values if x is not None]
    out = {"finest": v[-1] if v else None, "order": None, "extrapolated": None,
           "error_estimate": None, "monotone": False, "meshes_used": len(v)}
    if len(v) < 3:
        if len(v) == 2:
            out["error_estimate"] = abs(v[1] - v[0])
        return out
    f1, f2, f3 = v[-3:]
    d1, d2 = f2 - f1, f3 - f2
    if d1 == 0.0 and d2 == 0.0:
        out.update(monotone=True, extrapolated=f3, error_estimate=0.0)
        return out
    if d1 * d2 > 0 and abs(d2) < abs(d1):
        p = math.log(abs(d1 / d2)) / math.log(ratio)
        if p < 1.0:
            out.update(monotone=True, order=p, error_estimate=max(abs(d1), abs(d2)))
            return out
        pe = min(p, 4.0)
        corr = d2 / (ratio ** pe - 1.0)
        out.update(monotone=True, order=p, extrapolated=f3 + corr,
                   error_estimate=safety * abs(corr))
    else:
        out["error_estimate"] = max(abs(d1), abs(d2))
    return out


HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
RESULTS = os.path.join(REPO, "validation", "results")


def fmt(st):
    """'finest (extrapolated +- error)' for logs."""
    f, x, e = st.get("finest"), st.get("extrapolated"), st.get("error_estimate")
    s = f"{f:.6g}" if f is not None else "n/a"
    if x is not None:
        s += f" (extrapolated {x:.6g}"
    else:
        s += " (not monotone"
    if e is not None:
        s += f", error {e:.2g})"
    else:
        s += ")"
    return s


def polyline_json(line, digits=10):
    return [[float(f"{x:.{digits}g}"), float(f"{y:.{digits}g}")] for x, y in line]


def material_json():
    return {"model": "compressible neo-Hookean, plane strain: psi = mu/2 (I1 - 3) - mu ln J "
                     "+ lambda/2 (ln J)^2, I1 = C11 + C22 + 1, J = det F (2x2)",
            "E": E_MOD, "nu": NU, "mu": MU, "lambda": LAM, "units": "SI; forces per unit "
            "depth (N/m)"}


def formulation_json():
    return {"element": "P2 (6-node quadratic triangle), displacement only, total Lagrangian; "
                       "element integrals with 6-point (degree 4) Gauss quadrature",
            "solver": "Newton with an energy line search; Levenberg-Marquardt (trust-region) "
                      "fallback on the energy; adaptive load stepping with secant predictor",
            "tolerance": "|r_free| <= 1e-6 E L (L = 3 mm punching: 3 N/m; 2 mm pulling: 2 N/m)",
            "library": "scikit-fem (mesh, basis, dof numbering) + numpy/scipy kernels"}


def logger():
    def log(msg):
        print(msg, flush=True)
    return log


def environment():
    return {"python": platform.python_version(), "numpy": np.__version__,
            "scipy": scipy.__version__, "scikit-fem": _skfem_version(),
            "machine": platform.machine()}


def _skfem_version():
    try:
        from importlib.metadata import version
        return version("scikit-fem")
    except Exception:
        return "unknown"


def command_line():
    script = os.path.relpath(os.path.abspath(sys.argv[0]), REPO)
    return " ".join(["python3", script] + sys.argv[1:])


def write_json(path, obj):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as fh:
        json.dump(obj, fh, indent=1)
        fh.write("\n")


class Clock:
    def __init__(self):
        self.t0 = time.perf_counter()

    def __call__(self):
        return time.perf_counter() - self.t0
