"""Punching strip (TL paper sec. 4.2): plane-strain finite-element reference.

Strip W x H = 9 mm x 3 mm (x in [-W/2, W/2], y in [-H/2, H/2]), compressible neo-Hookean
(E = 1 GPa, nu = 0.45), pressed between two rigid frictionless punches (boxes pw x 0.3 mm,
centred at x = 0) that each move toward the centre by delta = c H / 2. See README.md.
"""
from __future__ import annotations

import argparse
import sys
import time

import numpy as np

import common as C

W, H, T = 9e-3, 3e-3, 0.3e-3
COMPRESSIONS = (0.1, 0.2, 0.3, 0.4, 0.5)
LEVELS = (0, 1, 2)
HOMOGENEOUS_STABLE_MAX_C = 0.4  # lambda_y >= 0.6 > 0.58 (issue 10: stability limit ~0.58)
CORNER_RADIUS = T / 2  # punch corner radius of the reference (README: "Punch corners")
SMALL_CORNER_RADIUS = 50e-6  # the earlier reference's radius, kept as a check
FINE_STEP = 0.01  # the mesh study records every FINE_STEP of compression (README: "Load path")
SMOOTHING_HALF_WIDTH = 0.05  # reported value: quadratic fit over c +- this
CONTACT_TEXT = ("node-to-rigid-box, frictionless: the P2 nodes of the strip's outer boundary "
                "against each punch's signed-distance function g (corners rounded, r = 0.15 mm, "
                "half the punch thickness); "
                "nodal force "
                "p w grad g with w the node's Simpson share of the reference boundary length and "
                "p = max(0, pbar - eps g), eps = 100 E / h; Uzawa augmented Lagrangian: one "
                "multiplier update per load step, converged to max |g| under pressure <= 1e-7 H "
                "at every reported compression")


# ----------------------------------------------------------------------------- mesh
def quarter_mesh(level: int):
    """Quarter x in [0, W/2], y in [0, H/2]. Base: a tensor grid, finer (0.25 mm) over
    x in [2.5, 4.5] mm (the top-surface material that slides past the punch corner up to
    c = 0.5 comes from there), refined once more toward the top surface in that band
    (element edge 125 um along the top surface), then `level` uniform refinements (each halves
    every element: refinement ratio exactly 2)."""
    mm = 1e-3
    xs = np.concatenate([np.arange(0.0, 2.5, 0.5), np.arange(2.5, 4.5 + 1e-9, 0.25)]) * mm
    ys = np.array([0.0, 0.5, 0.9, 1.2, 1.4, 1.5]) * mm
    m = C.tensor_quarter(xs, ys)
    m = C.refine_where(m, lambda x, y: (x > 2.4 * mm) & (y > 0.9 * mm))
    if level > 0:
        m = m.refined(level)
    return m


def band_h(level: int) -> float:
    """Element edge along the top surface in the refined band."""
    return 0.25e-3 / 2 / 2 ** level


# ----------------------------------------------------------------------------- problem
class Punching:
    def __init__(self, level, pw=W, full=False, kappa=100.0, corner_radius=0.0):
        q = quarter_mesh(level)
        self.mesh = C.mirror_full(q) if full else q
        self.full, self.pw, self.level = full, pw, level
        m = self.mesh
        bf = m.boundary_facets()
        mid = m.p[:, m.facets[:, bf]].mean(axis=1)
        eps = 1e-9
        self.top = bf[np.abs(mid[1] - H / 2) < eps]
        self.bottom = bf[np.abs(mid[1] + H / 2) < eps]
        self.sides = bf[np.abs(np.abs(mid[0]) - W / 2) < eps]
        outer = np.concatenate([self.top, self.sides] + ([self.bottom] if full else []))
        self.outer = outer
        self.pr = C.Problem(m, contact_facets=outer, kappa=kappa, length_scale=H)
        pr = self.pr
        if full:
            # gauge: the frictionless strip may translate along x; pin u_x of the centre node
            self.fixed = pr.dofs_where(lambda x, y: (np.abs(x) < eps) & (np.abs(y) < eps), (0,))
        else:
            self.fixed = np.concatenate([pr.dofs_where(lambda x, y: np.abs(x) < eps, (0,)),
                                         pr.dofs_where(lambda x, y: np.abs(y) < eps, (1,))])
        pr.set_fixed(self.fixed)
        self.top_box = C.RigidBox(0.0, H / 2 + T / 2, pw / 2, T / 2, "top", r=corner_radius)
        boxes = [self.top_box]
        if full:
            self.bottom_box = C.RigidBox(0.0, -H / 2 - T / 2, pw / 2, T / 2, "bottom",
                                         r=corner_radius)
            boxes.append(self.bottom_box)
        pr.set_boxes(boxes)
        self.tol_pen = 1e-7 * H

    def apply(self, c, u):
        d = c * H / 2
        self.top_box.cy = H / 2 - d + T / 2
        if self.full:
            self.bottom_box.cy = -H / 2 + d - T / 2
        u[self.fixed] = 0.0

    def predictor(self, c, u):
        """Linear plane-strain homogeneous compression (first step only)."""
        v = u.copy()
        v[self.pr.node_dofs[1]] = -c * self.pr.X[1]
        v[self.pr.node_dofs[0]] = C.NU / (1 - C.NU) * c * self.pr.X[0]
        return v

    # ------------------------------------------------------------------ measurements
    def measure(self, c, u):
        pr = self.pr
        f = pr.box_forces(u)
        mult = 1.0 if self.full else 2.0  # quarter model: half of the punch
        force = -f[0][1] * mult  # compressive force the top punch exerts, N/m
        side_x = pr.boundary_curve(u, self.sides, 8)[0][0]
        bulge = float(np.max(np.abs(side_x)) / (W / 2))
        a, a0 = pr.area_integral(u)
        area_change = a / a0 - 1.0
        contact = self.contact_length(u) * mult
        out = {"force": float(force), "bulge": bulge, "area_change": float(area_change),
               "contact_length": float(contact),
               "side_face_force_x": float(abs(f[0][0]) * (1.0 if self.full else 1.0))}
        if self.full:
            out["force_bottom"] = float(f[1][1])
            out["bulge_left"] = float(-np.min(side_x) / (W / 2))
            out["bulge_right"] = float(np.max(side_x) / (W / 2))
        return out

    def contact_length(self, u):
        """Current length of the strip boundary pressed by the top punch: per boundary facet,
        its two halves (vertex-midside, midside-vertex) count fully when both of their nodes
        carry pressure and half when one does (resolution: half a facet)."""
        pr = self.pr
        g, n, Hs, p = pr.contact_state(u)[0]
        active = np.zeros(pr.X.shape[1], dtype=bool)
        active[pr.cnodes[p > 0]] = True
        m = self.mesh
        nv = m.p.shape[1]
        x = pr.current_nodes(u)
        total = 0.0
        for fi in self.outer:
            v0, v1, vm = m.facets[0, fi], m.facets[1, fi], nv + fi
            for a, b in ((v0, vm), (vm, v1)):
                w = 0.5 * (int(active[a]) + int(active[b]))
                if w > 0:
                    total += w * float(np.linalg.norm(x[:, a] - x[:, b]))
        return total

    def polyline(self, u):
        """Deformed outer boundary of the whole strip, closed, counter-clockwise, from
        (0, -H/2) (metres). Quarter model: mirrored."""
        pr = self.pr
        facets = self.outer
        order, fwd = pr.boundary_chain(facets, self._start_pred())
        pts, _, _ = pr.boundary_curve(u, order, 2)
        pts = np.where(fwd[None, :, None], pts, pts[:, :, ::-1])
        line = [pts[:, 0, 0]] + [pts[:, k, j] for k in range(pts.shape[1]) for j in (1, 2)]
        line = np.array(line)
        if self.full:
            area = 0.5 * np.sum(line[:-1, 0] * line[1:, 1] - line[1:, 0] * line[:-1, 1])
            return line if area > 0 else line[::-1]
        # quarter chain runs from (0, H/2) along the top to the side and down to (W/2, 0)
        if line[0, 0] > line[-1, 0]:
            line = line[::-1]
        q1 = line  # (0, top) -> (right, 0)
        q4 = q1[::-1] * np.array([1, -1])  # (right, 0) -> (0, -top)
        right = np.vstack([q4[::-1][:-1], q1[::-1]])  # (0,-top) -> (right,0) -> (0, top)
        left = right[::-1] * np.array([-1, 1])
        return np.vstack([right, left[1:]])

    def _start_pred(self):
        if self.full:
            return lambda x, y: abs(x) < 1e-12 and abs(y + H / 2) < 1e-12
        return lambda x, y: abs(x) < 1e-12 and abs(y - H / 2) < 1e-12


def run_path(level, cs, pw=W, full=False, kappa=100.0, corner_radius=CORNER_RADIUS, eig=False,
             log=None, keep=False):
    """Load path to max(cs); returns ({c: measurements}, {c: polyline}, info)."""
    P = Punching(level, pw=pw, full=full, kappa=kappa, corner_radius=corner_radius)
    pr = P.pr
    res, lines, states = {}, {}, {}
    eigs = []

    def cb(c, u):
        res[c] = P.measure(c, u)
        lines[c] = P.polyline(u)
        if keep:
            states[c] = u.copy()

    def ec(c, u):
        eigs.append((float(c), pr.negative_eigenvalues(u)))

    clock = C.Clock()
    t_end, u = pr.follow(np.zeros(pr.N), P.apply, list(cs), cb, dt0=0.01, dt_max=0.025,
                         tol_pen=P.tol_pen, predictor=P.predictor, log=log,
                         eig_check=ec if eig else None)
    info = {"reached": float(t_end), "seconds": clock(), "dofs": int(pr.N),
            "elements": int(P.mesh.t.shape[1]), "stats": dict(pr.stats),
            "band_element_edge_m": band_h(level)}
    if eig:
        info["negative_eigenvalues"] = eigs
    if keep:
        info["states"] = states
        info["problem"] = P
    return res, lines, info


def fine_compressions():
    """The load-path targets of the mesh study: every FINE_STEP from 0.05 to the largest
    reported compression, plus the reported ones."""
    n = int(round((max(COMPRESSIONS) - 0.05) / FINE_STEP))
    cs = {round(0.05 + k * FINE_STEP, 6) for k in range(n + 1)} | set(COMPRESSIONS)
    return sorted(cs)


def smoothed(res, c, key):
    """The value of `key` at compression c from a least-squares quadratic through the recorded
    values within +- SMOOTHING_HALF_WIDTH (one-sided at the end of the path): node-to-surface
    contact makes the force a saw-tooth (a node holds at the punch corner, then slips off),
    whose phase at one exact compression depends on the mesh; the fit takes its mean."""
    pts = [(x, v[key]) for x, v in res.items() if abs(x - c) <= SMOOTHING_HALF_WIDTH + 1e-9]
    if len(pts) < 4:
        return res[c][key]
    x = np.array([p[0] for p in pts]) - c
    y = np.array([p[1] for p in pts])
    coef = np.polyfit(x, y, 2)
    return float(np.polyval(coef, 0.0))


def homogeneous_check(log, level):
    """Punches 3 W wide: the strip is compressed homogeneously; force and width must match the
    closed form (relative 1e-4) while the homogeneous state is stable. Below lambda_y ~ 0.58
    (c > 0.42) it is not (the free sides wrinkle/barrel, issue 10): there the solver, which only
    stops in energy minima, may leave it; that is recorded, not asserted (the inertia of the
    full model's tangent in checks.homogeneous_stability shows where it turns unstable)."""
    res, _, info = run_path(level, COMPRESSIONS, pw=3 * W)
    rows = []
    for c in COMPRESSIONS:
        lx, pyy = C.homogeneous_plane_strain(1.0 - c)
        f_ref = -pyy * W
        r = res[c]
        ef, ew = abs(r["force"] / f_ref - 1.0), abs(r["bulge"] / lx - 1.0)
        ea = abs((1 + r["area_change"]) / (lx * (1 - c)) - 1.0)
        stable_range = c <= HOMOGENEOUS_STABLE_MAX_C
        rows.append({"compression": c, "force_fem": r["force"], "force_closed_form": f_ref,
                     "force_rel_error": ef, "width_fem": r["bulge"], "width_closed_form": lx,
                     "width_rel_error": ew, "area_rel_error": ea, "asserted": stable_range,
                     "left_homogeneous_state": bool(max(ef, ew, ea) > 1e-4)})
        log(f"homogeneous check pw = 3W, c = {c}: force {r['force']:.9e} vs {f_ref:.9e} "
            f"(rel {ef:.1e}), width {r['bulge']:.9f} vs {lx:.9f} (rel {ew:.1e})"
            + ("" if stable_range else " [beyond the stability limit: not asserted]"))
        if stable_range:
            assert ef <= 1e-4 and ew <= 1e-4 and ea <= 1e-4, "homogeneous punching check failed"
    return {"level": level, "punch_width": 3 * W, "tolerance": 1e-4, "rows": rows,
            "seconds": info["seconds"]}


def stability_path(log, level, pw, cs):
    """Full model (mirror-symmetric mesh, both punches): negative eigenvalues of the tangent
    after every load step; where the count turns positive the symmetric path has bifurcated."""
    res, lines, info = run_path(level, cs, pw=pw, full=True, eig=True)
    neg = info["negative_eigenvalues"]
    first = next((c for c, n in neg if n > 0), None)
    log(f"full model pw = {pw / W:g} W, level {level}: reached c = {info['reached']:.4g}; "
        f"first load step with a negative tangent eigenvalue: {first} "
        f"({len(neg)} steps checked, {info['seconds']:.0f} s)")
    return res, lines, info, first


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--quick", action="store_true", help="levels 0-1 only, no JSON")
    ap.add_argument("--out", default=C.os.path.join(C.RESULTS, "fem-punching.json"))
    a = ap.parse_args()
    log = C.logger()
    clock = C.Clock()
    levels = (0, 1) if a.quick else LEVELS
    checks = {}
    failures = []  # checks that need the long runs: recorded, reported, exit status 1 at the end
    checks["homogeneous"] = homogeneous_check(log, 0)

    # mesh study, quarter model, punch width W (level 0 first: the checks below use it)
    per_level = []
    runs = []

    def study(lev):
        res, lines, info = run_path(lev, fine_compressions())
        log(f"pw = W, level {lev}: {info['dofs']} dofs, band element {band_h(lev) * 1e6:.1f} um, "
            f"reached c = {info['reached']:.4g} in {info['seconds']:.0f} s {info['stats']}")
        for c, v in res.items():
            log(f"  level {lev} c = {c}: " + ", ".join(f"{k} {x:.7g}" for k, x in v.items()))
        per_level.append((lev, res, lines, info))
        runs.append({"punch_width": W, "level": lev, "dofs": info["dofs"],
                     "elements": info["elements"], "band_element_edge_m": band_h(lev),
                     "reached_compression": info["reached"], "seconds": info["seconds"],
                     "stats": info["stats"]})

    study(levels[0])

    # symmetry and stability: full model at level 0, compared with the quarter model
    f_res, f_lines, f_info, first_neg = stability_path(log, 0, W, fine_compressions())
    q0 = per_level[0][1]
    sym = {}
    for c in COMPRESSIONS:
        if c in f_res and c in q0:
            sym[c] = {k: abs(f_res[c][k] / q0[c][k] - 1.0)
                      for k in ("force", "bulge", "area_change")}
            sym[c]["top_bottom_force"] = abs(f_res[c]["force_bottom"] / f_res[c]["force"] - 1)
            sym[c]["left_right_bulge"] = abs(f_res[c]["bulge_left"] / f_res[c]["bulge_right"]
                                             - 1)
    log(f"full vs quarter (level 0): {sym}")
    sym_ok = 0.3 in sym and max(sym[0.3].values()) < 1e-3
    if not sym_ok:
        failures.append("symmetry: full and quarter models differ by >= 1e-3 at c = 0.3")
    checks["symmetry"] = {"level": 0, "passed": bool(sym_ok), "relative_differences": {str(c): v for c, v in sym.items()},
                          "tolerance_at_c_0.3": 1e-3,
                          "negative_tangent_eigenvalues": f_info["negative_eigenvalues"],
                          "first_unstable_compression": first_neg,
                          "seconds": f_info["seconds"]}
    # bifurcation of the homogeneous state (punches 3 W wide), for comparison
    h_res, _, h_info, h_first = stability_path(log, 0, 3 * W, COMPRESSIONS)
    checks["homogeneous_stability"] = {"level": 0, "punch_width": 3 * W,
                                       "negative_tangent_eigenvalues":
                                           h_info["negative_eigenvalues"],
                                       "first_unstable_compression": h_first,
                                       "seconds": h_info["seconds"]}

    # contact: penalty independence (augmented Lagrangian) and corner sensitivity
    k_res, _, k_info = run_path(0, fine_compressions(), kappa=1000.0)
    kd = {str(c): {k: abs(k_res[c][k] / q0[c][k] - 1.0) for k in ("force", "bulge", "area_change")}
          for c in COMPRESSIONS if c in k_res and c in q0}
    log(f"penalty x10 (level 0): relative changes {kd}")
    # The stiffer penalty's path may stop short of 50 % (its Newton steps fail where the strip
    # has several equilibria); it must reach 30 %, and agree where it went.
    pen_ok = (k_info["reached"] >= 0.3 - 1e-9 and len(kd) > 0
              and all(max(v.values()) < 1e-3 for v in kd.values()))
    if not pen_ok:
        failures.append("penalty: results change by >= 0.1 % with the penalty x10")
    checks["penalty"] = {"level": 0, "passed": bool(pen_ok), "kappa": [100.0, 1000.0],
                         "relative_changes": kd, "reached": k_info["reached"],
                         "tolerance": 1e-3, "seconds": k_info["seconds"]}
    # load path: the coarse path (the reported compressions only, adaptive steps between) on
    # the same mesh; at 40-50 % the strip has several equilibria and the path picks one
    p_res, _, p_info = run_path(0, COMPRESSIONS)
    pd = {str(c): {k: p_res[c][k] / q0[c][k] - 1.0 for k in ("force", "bulge", "area_change")}
          for c in COMPRESSIONS if c in p_res and c in q0}
    log(f"coarse load path instead of every {FINE_STEP} (level 0): relative changes {pd}")
    checks["load_path"] = {"level": 0, "fine_step": FINE_STEP,
                           "relative_changes_coarse_vs_fine": pd, "seconds": p_info["seconds"]}
    for lev in levels[1:]:
        study(lev)
    q1 = per_level[1][1]
    s_res, _, s_info = run_path(1, COMPRESSIONS, corner_radius=SMALL_CORNER_RADIUS)
    sd = {str(c): {k: s_res[c][k] / q1[c][k] - 1.0 for k in ("force", "bulge", "area_change")}
          for c in COMPRESSIONS if c in s_res and c in q1}
    log(f"corners r = {SMALL_CORNER_RADIUS * 1e6:.0f} um instead of {CORNER_RADIUS * 1e6:.0f} um "
        f"(level 1, exact compressions, coarse load steps): relative changes {sd}")
    checks["small_corner_radius"] = {"level": 1, "radius": SMALL_CORNER_RADIUS,
                                     "compared_with": CORNER_RADIUS,
                                     "relative_changes_small_vs_reference": sd,
                                     "values": {str(c): v for c, v in s_res.items()},
                                     "seconds": s_info["seconds"]}
    r_res, _, r_info = run_path(1, COMPRESSIONS, corner_radius=0.0)
    rd = {str(c): {k: r_res[c][k] / q1[c][k] - 1.0 for k in ("force", "bulge", "area_change",
                                                           "contact_length")}
          for c in COMPRESSIONS if c in r_res and c in q1}
    log(f"sharp punch corners instead of r = {CORNER_RADIUS * 1e6:.0f} um (level 1): relative "
        f"changes {rd}")
    checks["corner_radius"] = {"level": 1, "radius": CORNER_RADIUS, "compared_with": 0.0,
                               "relative_changes_sharp_vs_rounded": rd,
                               "sharp": {str(c): v for c, v in r_res.items()},
                               "reached_sharp": r_info["reached"],
                               "seconds": r_info["seconds"]}

    entries = []
    for c in COMPRESSIONS:
        avail = [(lev, r, lines, info) for lev, r, lines, info in per_level if c in r]
        if not avail:
            continue
        entry = {"params": {"W": W, "H": H, "punch_width": W, "punch_thickness": T,
                            "compression": c, "delta": c * H / 2,
                            "corner_radius": CORNER_RADIUS},
                 "levels": [lev for lev, *_ in avail],
                 "dofs": [info["dofs"] for *_, info in avail]}
        for k in ("force", "bulge", "area_change", "contact_length", "side_face_force_x"):
            v = [smoothed(r, c, k) for _, r, _, _ in avail]
            raw = [r[c][k] for _, r, _, _ in avail]
            entry[k] = {"per_mesh": v, "per_mesh_unsmoothed": raw, **C.richardson(v)}
        entry["fine_path"] = {str(lev): {"compression": sorted(r),
                                         "force": [r[x]["force"] for x in sorted(r)]}
                              for lev, r, _, _ in avail}
        entry["boundary_polyline"] = {"level": avail[-1][0],
                                      "xy": C.polyline_json(avail[-1][2][c])}
        entry["command"] = C.command_line()
        entries.append(entry)
        log(f"  c = {c}: force {C.fmt(entry['force'])} N/m, bulge {C.fmt(entry['bulge'])}, "
            f"area change {C.fmt(entry['area_change'])}, contact length "
            f"{C.fmt(entry['contact_length'])} m")
    out = {"case": "punching-strip-2d, plane-strain FEM reference (frictionless rigid punches)",
           "schema": "validation/fem/README.md#json-schema",
           "command": C.command_line(), "environment": C.environment(),
           "material": C.material_json(), "formulation": C.formulation_json(),
           "contact": CONTACT_TEXT,
           "mesh_study": {"levels": list(levels), "refinement_ratio": 2,
                          "base": quarter_mesh.__doc__.strip()},
           "checks": checks, "runs": runs, "entries": entries, "total_seconds": clock()}
    out["failed_checks"] = failures
    if not a.quick:
        C.write_json(a.out, out)
        log(f"wrote {C.os.path.relpath(a.out)} in {clock():.0f} s")
    else:
        log(f"quick run done in {clock():.0f} s (no JSON written)")
    for f in failures:
        log(f"CHECK FAILED: {f}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
