"""Pulling strip with clamped grips (TL paper sec. 4.3): plane-strain finite-element reference.

Rectangle W_p x H_p (W_p = 2 mm; x in [-W_p/2, W_p/2], y in [-H_p/2, H_p/2]), compressible
neo-Hookean (E = 1 GPa, nu = 0.45); top edge u = (0, +delta), bottom edge u = (0, -delta)
(clamped), sides free; stretch lambda = 1 + 2 delta / H_p. Quarter model (symmetry about both
axes; checked against the full model). See README.md.

    python3 validation/fem/pulling.py            # full reference -> validation/results/fem-pulling.json
    python3 validation/fem/pulling.py --quick    # coarse meshes only, no JSON (smoke test)
"""
from __future__ import annotations

import argparse
import os
import sys

import numpy as np

import common as C

WP = 2e-3
ASPECTS = {"1": 1.0, "19/20": 19 / 20, "29/30": 29 / 30, "44/45": 44 / 45}
STRETCHES = (1.5, 2.0, 3.0)
CONTINUE = (4.0, 5.0, 6.0)
LEVELS = (0, 1, 2)
BASE_N = 8  # quarter base mesh: BASE_N x BASE_N cells, graded 4:1 toward the grip corner


def quarter_mesh(hp, level):
    """Quarter [0, W_p/2] x [0, H_p/2]: a tensor grid graded (ratio 4 between the largest and the
    smallest spacing) toward the free side x = W_p/2 and the grip y = H_p/2, i.e. toward the
    clamped corner where the stress is singular; then `level` uniform refinements (ratio 2)."""
    m = C.symmetric_mesh(WP / 2, hp / 2, BASE_N, BASE_N, 4.0, 4.0, quarter=True)
    return m.refined(level) if level > 0 else m


class Pulling:
    def __init__(self, hp, level, clamped=True, full=False):
        self.hp, self.level, self.clamped, self.full = hp, level, clamped, full
        q = quarter_mesh(hp, level)
        self.mesh = C.mirror_full(q) if full else q
        pr = self.pr = C.Problem(self.mesh, length_scale=WP)
        eps = 1e-12
        self.top_y = pr.dofs_where(lambda x, y: np.abs(y - hp / 2) < eps, (1,))
        self.top_x = pr.dofs_where(lambda x, y: np.abs(y - hp / 2) < eps, (0,))
        fixed = [self.top_y]
        if clamped:
            fixed.append(self.top_x)
        if full:
            self.bot_y = pr.dofs_where(lambda x, y: np.abs(y + hp / 2) < eps, (1,))
            self.bot_x = pr.dofs_where(lambda x, y: np.abs(y + hp / 2) < eps, (0,))
            fixed.append(self.bot_y)
            if clamped:
                fixed.append(self.bot_x)
            else:  # rollers: pin the horizontal translation at the centre
                fixed.append(pr.dofs_where(lambda x, y: (np.abs(x) < eps) & (np.abs(y) < eps),
                                           (0,)))
        else:
            self.sym_x = pr.dofs_where(lambda x, y: np.abs(x) < eps, (0,))
            self.sym_y = pr.dofs_where(lambda x, y: np.abs(y) < eps, (1,))
            fixed += [self.sym_x, self.sym_y]
        self.fixed = np.concatenate(fixed)
        pr.set_fixed(self.fixed)
        m = self.mesh
        bf = m.boundary_facets()
        mid = m.p[:, m.facets[:, bf]].mean(axis=1)
        self.sides = bf[np.abs(np.abs(mid[0]) - WP / 2) < 1e-12]
        self.grips = bf[np.abs(np.abs(mid[1]) - hp / 2) < 1e-12]
        self.outer = np.concatenate([self.sides, self.grips])

    def apply(self, lam, u):
        d = (lam - 1.0) * self.hp / 2
        u[self.fixed] = 0.0
        u[self.top_y] = d
        if self.full:
            u[self.bot_y] = -d

    def predictor(self, lam, u):
        v = u.copy()
        v[self.pr.node_dofs[1]] = (lam - 1.0) * self.pr.X[1]
        return v

    def measure(self, lam, u):
        pr = self.pr
        mult = 1.0 if self.full else 2.0
        force = pr.reaction(u, self.top_y) * mult
        x = pr.current_nodes(u)
        on_side = np.abs(np.abs(pr.X[0]) - WP / 2) < 1e-12
        at_mid = on_side & (np.abs(pr.X[1]) < 1e-12)
        # by symmetry the material point (W_p/2, 0) stays at y = 0 (checked on the full model)
        if self.full:
            right = x[0][at_mid & (pr.X[0] > 0)][0]
            left = x[0][at_mid & (pr.X[0] < 0)][0]
            width = right - left
            mid_y = float(max(abs(x[1][at_mid & (pr.X[0] > 0)][0]),
                              abs(x[1][at_mid & (pr.X[0] < 0)][0])))
        else:
            width = 2.0 * x[0][at_mid][0]
            mid_y = 0.0
        side_x = pr.boundary_curve(u, self.sides, 8)[0][0]
        a, a0 = pr.area_integral(u)
        F = pr.deformation_gradient(u)
        jmax = float(np.max(F[0, 0] * F[1, 1] - F[0, 1] * F[1, 0]))
        out = {"force": float(force), "neck_width": float(width / WP), "max_J": jmax,
               "min_width": float(2 * np.min(np.abs(side_x)) / WP) if not self.full else
               float((np.min(side_x[side_x > 0]) - np.max(side_x[side_x < 0])) / WP),
               "area_change": float(a / a0 - 1.0)}
        if self.full:
            out["mid_point_y_offset"] = mid_y
            out["force_bottom"] = float(-pr.reaction(u, self.bot_y))
        return out

    def polyline(self, u):
        """Deformed outer boundary (closed, counter-clockwise, metres). Quarter: mirrored."""
        pr = self.pr
        start = (lambda x, y: abs(x) < 1e-12 and abs(y - self.hp / 2) < 1e-12)
        if self.full:
            start = (lambda x, y: abs(x - WP / 2) < 1e-12 and abs(y + self.hp / 2) < 1e-12)
        order, fwd = pr.boundary_chain(self.outer, start)
        pts, _, _ = pr.boundary_curve(u, order, 2)
        pts = np.where(fwd[None, :, None], pts, pts[:, :, ::-1])
        line = np.array([pts[:, 0, 0]] + [pts[:, k, j] for k in range(pts.shape[1])
                                          for j in (1, 2)])
        if self.full:
            return line
        if line[0, 0] > line[-1, 0]:
            line = line[::-1]
        q1 = line  # (0, top) -> (right, top) -> (right, 0)
        q4 = q1[::-1] * np.array([1, -1])
        right = np.vstack([q4[::-1][:-1], q1[::-1]])
        left = right[::-1] * np.array([-1, 1])
        return np.vstack([right, left[1:]])


def run_path(hp, level, stretches, clamped=True, full=False, eig=False, log=None):
    P = Pulling(hp, level, clamped=clamped, full=full)
    pr = P.pr
    res, lines, eigs = {}, {}, []

    def cb(lam, u):
        res[lam] = P.measure(lam, u)
        lines[lam] = P.polyline(u)

    def ec(lam, u):
        eigs.append((float(lam), pr.negative_eigenvalues(u)))

    clock = C.Clock()
    t_end, _ = pr.follow(np.zeros(pr.N), P.apply, list(stretches), cb, dt0=0.05, dt_max=0.25,
                         predictor=P.predictor, log=log, eig_check=ec if eig else None,
                         t0=1.0, dt_min=1e-4)
    info = {"reached": float(t_end), "seconds": clock(), "dofs": int(pr.N),
            "elements": int(P.mesh.t.shape[1]), "h_min": pr.h_min, "stats": dict(pr.stats)}
    if eig:
        info["negative_eigenvalue_count"] = eigs
    return res, lines, info


def homogeneous_check(log):
    """Roller grips at stretch 2: the FEM state is homogeneous and must match the closed form."""
    lam = 2.0
    res, _, info = run_path(WP, 0, [lam], clamped=False)
    lx, pyy = C.homogeneous_plane_strain(lam)
    f_ref = pyy * WP
    r = res[lam]
    err_f = abs(r["force"] / f_ref - 1.0)
    err_w = abs(r["neck_width"] / lx - 1.0)
    log(f"homogeneous check (roller grips, stretch 2): force {r['force']:.9e} vs closed form "
        f"{f_ref:.9e} (rel {err_f:.1e}); width {r['neck_width']:.9f} vs {lx:.9f} "
        f"(rel {err_w:.1e})")
    assert err_f <= 1e-4 and err_w <= 1e-4, "homogeneous pulling check failed"
    return {"stretch": lam, "force_fem": r["force"], "force_closed_form": f_ref,
            "force_rel_error": err_f, "width_fem": r["neck_width"], "width_closed_form": lx,
            "width_rel_error": err_w, "tolerance": 1e-4, "seconds": info["seconds"]}


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true",
                    help="levels 0-1, aspect 1 only, no JSON (smoke test)")
    ap.add_argument("--out", default=os.path.join(C.RESULTS, "fem-pulling.json"))
    a = ap.parse_args()
    log = C.logger()
    clock = C.Clock()
    levels = (0, 1) if a.quick else LEVELS
    aspects = {"1": 1.0} if a.quick else ASPECTS
    targets = list(STRETCHES) + list(CONTINUE)

    checks = {"homogeneous": homogeneous_check(log)}

    # symmetry: full model vs quarter model (aspect 1, level 1, stretch 2), and stability of
    # the full model along the path (inertia of the tangent)
    full_res, _, full_info = run_path(WP, 1, [1.5, 2.0, 3.0], full=True, eig=True)
    q_res, _, _ = run_path(WP, 1, [1.5, 2.0, 3.0])
    diffs = {k: abs(full_res[2.0][k] / q_res[2.0][k] - 1.0)
             for k in ("force", "neck_width", "area_change")}
    neg = [n for _, n in full_info["negative_eigenvalue_count"]]
    log(f"full vs quarter model at stretch 2 (level 1): relative differences {diffs}; "
        f"mid-height point y offset {full_res[2.0]['mid_point_y_offset']:.2e} m; "
        f"negative tangent eigenvalues along the full-model path: max {max(neg)}")
    assert max(diffs.values()) < 1e-6, "quarter model differs from the full model"
    checks["symmetry"] = {"level": 1, "stretch": 2.0, "relative_differences": diffs,
                          "full_model": full_res[2.0], "quarter_model": q_res[2.0],
                          "max_negative_eigenvalues_on_path": int(max(neg)),
                          "path_points_checked": len(neg), "seconds": full_info["seconds"]}

    entries, runs = [], []
    for name, aspect in aspects.items():
        hp = aspect * WP
        per_level = []
        for lev in levels:
            res, lines, info = run_path(hp, lev, targets)
            log(f"aspect {name} level {lev}: {info['dofs']} dofs, reached stretch "
                f"{info['reached']:.4g} in {info['seconds']:.1f} s "
                f"({info['stats']['newton_iterations']} Newton iterations)")
            per_level.append((lev, res, lines, info))
            runs.append({"aspect": name, "level": lev, "dofs": info["dofs"],
                         "elements": info["elements"], "h_min_m": info["h_min"],
                         "reached_stretch": info["reached"], "seconds": info["seconds"],
                         "stats": info["stats"]})
        for lam in targets:
            vals = {k: [r.get(lam, {}).get(k) for _, r, _, _ in per_level]
                    for k in ("force", "neck_width", "min_width", "area_change", "max_J")}
            if all(v is None for v in vals["force"]):
                continue
            finest = [(lev, lines) for lev, r, lines, _ in per_level if lam in r][-1]
            entry = {"params": {"W_p": WP, "H_p": hp, "aspect": name, "stretch": lam,
                                "delta": (lam - 1) * hp / 2, "grips": "clamped"},
                     "levels": [lev for lev, r, _, _ in per_level if lam in r],
                     "dofs": [info["dofs"] for lev, r, _, info in per_level if lam in r]}
            for k, v in vals.items():
                st = C.richardson(v)
                entry[k] = {"per_mesh": v, **st}
            entry["boundary_polyline"] = {"level": finest[0],
                                          "xy": C.polyline_json(finest[1][lam])}
            entry["command"] = C.command_line()
            entries.append(entry)
            f, nw, ac = entry["force"], entry["neck_width"], entry["area_change"]
            log(f"  aspect {name} stretch {lam}: force {C.fmt(f)} N/m, neck width "
                f"{C.fmt(nw)}, area change {C.fmt(ac)}")
    out = {"case": "pulling-strip-2d (clamped grips), plane-strain FEM reference",
           "schema": "validation/fem/README.md#json-schema",
           "command": C.command_line(), "environment": C.environment(),
           "material": C.material_json(), "formulation": C.formulation_json(),
           "mesh_study": {"levels": list(levels), "refinement_ratio": 2,
                          "base": f"quarter {BASE_N}x{BASE_N} cells, graded 4:1 toward the "
                                  "clamped corner, P2 triangles"},
           "convexity_limit_J": C.J_CONVEXITY_LIMIT,
           "checks": checks, "runs": runs, "entries": entries,
           "total_seconds": clock()}
    if a.quick:
        log(f"quick run done in {clock():.0f} s (no JSON written)")
        return
    C.write_json(a.out, out)
    log(f"wrote {os.path.relpath(a.out)} in {clock():.0f} s")


if __name__ == "__main__":
    sys.exit(main())
