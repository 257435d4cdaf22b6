//! Triangle meshes: read from STL (ASCII or binary) and Wavefront OBJ, placed in the scene
//! ([`Placement`]: scale, rotate, translate), repaired (welded, degenerate and duplicated faces
//! dropped, orientation made consistent) and turned into a [`MeshSolid`]: a [`Shape`] whose
//! inside is decided by the generalized winding number, with the distance to its surface.
//!
//! ```
//! use sph_geometry::mesh::{MeshSolid, TriMesh};
//! use sph_geometry::{generate::Shape, glam::DVec3};
//!
//! // A unit cube from 12 triangles (any tessellation, any orientation).
//! let cube = TriMesh::cuboid(DVec3::ZERO, DVec3::ONE);
//! let solid = MeshSolid::new(cube, "cube")?;
//! assert!(solid.contains(DVec3::splat(0.5)) && !solid.contains(DVec3::splat(1.5)));
//! assert!((solid.volume() - 1.0).abs() < 1e-12);
//! # Ok::<(), sph_core::Error>(())
//! ```

use crate::bvh::Bvh;
use crate::file_error;
use crate::generate::Shape;
use crate::Boundary;
use glam::{DMat3, DQuat, DVec3};
use sph_core::error::Num;
use sph_core::{Error, D3};
use std::collections::HashMap;
use std::path::Path;

/// Where a mesh or outline goes in the scene: `x' = R (scale · x) + translate`, with `R` the
/// rotation by `degrees` about `axis` (right-handed; 2D outlines turn about `z`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// Uniform scale factor (`> 0`; e.g. `1e-3` for a part drawn in millimetres).
    pub scale: f64,
    /// Rotation axis (any length `> 0`).
    pub axis: DVec3,
    /// Rotation angle, degrees.
    pub degrees: f64,
    /// Translation, applied last.
    pub translate: DVec3,
}

impl Default for Placement {
    fn default() -> Self {
        Self {
            scale: 1.0,
            axis: DVec3::Z,
            degrees: 0.0,
            translate: DVec3::ZERO,
        }
    }
}

impl Placement {
    /// Checks the values: `scale` finite and `> 0`, `axis` finite and non-zero, `degrees` and
    /// `translate` finite; errors name the field.
    pub fn validate(&self) -> Result<(), Error> {
        sph_core::error::check_positive("scale", self.scale)?;
        if !(self.axis.is_finite() && self.axis.length() > 0.0) {
            return Err(Error::invalid(
                "rotate.axis",
                format!("{:?}", self.axis.to_array()),
                "finite and non-zero",
            ));
        }
        if !self.degrees.is_finite() {
            return Err(Error::invalid(
                "rotate.degrees",
                Num(self.degrees),
                "finite",
            ));
        }
        if !self.translate.is_finite() {
            return Err(Error::invalid(
                "translate",
                format!("{:?}", self.translate.to_array()),
                "finite",
            ));
        }
        Ok(())
    }

    /// The rotation matrix.
    pub fn rotation(&self) -> DMat3 {
        DMat3::from_quat(DQuat::from_axis_angle(
            self.axis.normalize(),
            self.degrees.to_radians(),
        ))
    }

    /// Where the point `x` of the file goes.
    pub fn apply(&self, x: DVec3) -> DVec3 {
        self.rotation() * (x * self.scale) + self.translate
    }
}

/// An indexed triangle mesh as read, before any repair.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriMesh {
    /// Vertex positions.
    pub vertices: Vec<DVec3>,
    /// Triangles as vertex indices, counter-clockwise seen from outside (repair fixes the
    /// orientation of a mesh that is not).
    pub triangles: Vec<[u32; 3]>,
}

impl TriMesh {
    /// Reads an STL (ASCII or binary, `.stl`) or Wavefront OBJ (`.obj`) file, by extension.
    /// Errors are one line naming the file.
    pub fn read(path: &Path) -> Result<Self, Error> {
        let name = path.display().to_string();
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(|e| e.to_ascii_lowercase());
        match ext.as_deref() {
            Some("stl") => Self::read_stl(path),
            Some("obj") => Self::read_obj(path),
            _ => Err(file_error(
                &name,
                "unknown mesh format: allowed extensions are .stl and .obj",
            )),
        }
    }

    /// Reads an STL file, ASCII or binary (through `stl_io`).
    pub fn read_stl(path: &Path) -> Result<Self, Error> {
        let name = path.display().to_string();
        let mut file = std::fs::File::open(path).map_err(|e| file_error(&name, e))?;
        let mesh = stl_io::read_stl(&mut file)
            .map_err(|e| file_error(&name, format!("not a readable STL file: {e}")))?;
        let vertices = mesh
            .vertices
            .iter()
            .map(|v| DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64))
            .collect();
        let triangles = mesh
            .faces
            .iter()
            .map(|f| f.vertices.map(|i| i as u32))
            .collect();
        Self::checked(vertices, triangles, &name)
    }

    /// Reads a Wavefront OBJ file (through `tobj`): every object and group, polygons
    /// triangulated; materials are not read.
    pub fn read_obj(path: &Path) -> Result<Self, Error> {
        let name = path.display().to_string();
        let options = tobj::LoadOptions {
            triangulate: true,
            single_index: true,
            ..Default::default()
        };
        let (models, _materials) = tobj::load_obj(path, &options)
            .map_err(|e| file_error(&name, format!("not a readable OBJ file: {e}")))?;
        let mut vertices = Vec::new();
        let mut triangles = Vec::new();
        for m in &models {
            let base = vertices.len() as u32;
            for p in m.mesh.positions.chunks_exact(3) {
                vertices.push(DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64));
            }
            for t in m.mesh.indices.chunks_exact(3) {
                triangles.push([base + t[0], base + t[1], base + t[2]]);
            }
        }
        Self::checked(vertices, triangles, &name)
    }

    /// A mesh from vertices and triangles, checked: indices in range, coordinates finite.
    pub fn new(vertices: Vec<DVec3>, triangles: Vec<[u32; 3]>) -> Result<Self, Error> {
        Self::checked(vertices, triangles, "mesh")
    }

    fn checked(vertices: Vec<DVec3>, triangles: Vec<[u32; 3]>, name: &str) -> Result<Self, Error> {
        if let Some(i) = vertices.iter().position(|v| !v.is_finite()) {
            return Err(file_error(name, format!("vertex {i} is not finite")));
        }
        let n = vertices.len() as u32;
        if let Some(t) = triangles.iter().position(|t| t.iter().any(|&i| i >= n)) {
            return Err(file_error(
                name,
                format!("triangle {t} names a vertex beyond the {n} vertices"),
            ));
        }
        Ok(Self {
            vertices,
            triangles,
        })
    }

    /// Writes the mesh as an ASCII STL file (for tests, examples and generated meshes).
    pub fn write_stl(&self, path: &Path) -> Result<(), Error> {
        use std::fmt::Write as _;
        let mut s = String::from("solid mesh\n");
        for t in &self.triangles {
            let [a, b, c] = t.map(|i| self.vertices[i as usize]);
            let n = (b - a).cross(c - a).normalize_or_zero();
            let _ = writeln!(s, "facet normal {:e} {:e} {:e}\n outer loop", n.x, n.y, n.z);
            for v in [a, b, c] {
                let _ = writeln!(s, "  vertex {:e} {:e} {:e}", v.x, v.y, v.z);
            }
            let _ = writeln!(s, " endloop\nendfacet");
        }
        s.push_str("endsolid mesh\n");
        std::fs::write(path, s).map_err(|e| file_error(&path.display().to_string(), e))
    }

    /// Writes the mesh as a binary STL file (50 bytes per triangle, single precision).
    pub fn write_stl_binary(&self, path: &Path) -> Result<(), Error> {
        let mut b = Vec::with_capacity(84 + 50 * self.triangles.len());
        let mut header = [b' '; 80];
        header[..14].copy_from_slice(b"sph-solids STL");
        b.extend(header);
        b.extend((self.triangles.len() as u32).to_le_bytes());
        for t in &self.triangles {
            let [a, p, c] = t.map(|i| self.vertices[i as usize]);
            let n = (p - a).cross(c - a).normalize_or_zero();
            for v in [n, a, p, c] {
                for x in [v.x, v.y, v.z] {
                    b.extend((x as f32).to_le_bytes());
                }
            }
            b.extend([0u8; 2]);
        }
        std::fs::write(path, b).map_err(|e| file_error(&path.display().to_string(), e))
    }

    /// The mesh with every vertex placed by `p`.
    pub fn placed(mut self, p: &Placement) -> Self {
        let r = p.rotation();
        for v in &mut self.vertices {
            *v = r * (*v * p.scale) + p.translate;
        }
        self
    }

    /// The triangles' corners.
    pub fn corners(&self) -> Vec<[DVec3; 3]> {
        self.triangles
            .iter()
            .map(|t| t.map(|i| self.vertices[i as usize]))
            .collect()
    }

    /// The axis-aligned bounds of the vertices used by triangles (`None` without triangles).
    pub fn bounds(&self) -> Option<(DVec3, DVec3)> {
        let mut it = self
            .triangles
            .iter()
            .flatten()
            .map(|&i| self.vertices[i as usize]);
        let first = it.next()?;
        Some(it.fold((first, first), |(lo, hi), v| (lo.min(v), hi.max(v))))
    }

    /// The enclosed volume of a closed, outward-oriented mesh, `(1/6) Σ v0·(v1×v2)` (relative
    /// to the centre of the bounds, which makes the value of a mesh with small holes
    /// independent of where it sits).
    pub fn volume(&self) -> f64 {
        let Some((lo, hi)) = self.bounds() else {
            return 0.0;
        };
        let o = 0.5 * (lo + hi);
        self.corners()
            .iter()
            .map(|[a, b, c]| (*a - o).dot((*b - o).cross(*c - o)))
            .sum::<f64>()
            / 6.0
    }

    /// The total area of the triangles.
    pub fn area(&self) -> f64 {
        self.corners()
            .iter()
            .map(|[a, b, c]| 0.5 * (*b - *a).cross(*c - *a).length())
            .sum()
    }

    /// A box `[lo, hi]` as 12 outward triangles.
    pub fn cuboid(lo: DVec3, hi: DVec3) -> Self {
        let v = (0..8)
            .map(|k| {
                DVec3::new(
                    if k & 1 == 0 { lo.x } else { hi.x },
                    if k & 2 == 0 { lo.y } else { hi.y },
                    if k & 4 == 0 { lo.z } else { hi.z },
                )
            })
            .collect();
        // Faces as quads (outward, counter-clockwise from outside).
        let quads = [
            [0, 2, 3, 1], // z = lo
            [4, 5, 7, 6], // z = hi
            [0, 1, 5, 4], // y = lo
            [2, 6, 7, 3], // y = hi
            [0, 4, 6, 2], // x = lo
            [1, 3, 7, 5], // x = hi
        ];
        let triangles = quads
            .iter()
            .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
            .collect();
        Self {
            vertices: v,
            triangles,
        }
    }

    /// A sphere of radius `r` about `centre`: a UV sphere of `n` segments around and `n/2`
    /// rings (`n ≥ 3`), outward.
    pub fn uv_sphere(centre: DVec3, r: f64, n: usize) -> Self {
        let n = n.max(3);
        let rings = (n / 2).max(2);
        let mut vertices = vec![centre + DVec3::Z * r, centre - DVec3::Z * r];
        for i in 1..rings {
            let theta = std::f64::consts::PI * i as f64 / rings as f64;
            for j in 0..n {
                let phi = 2.0 * std::f64::consts::PI * j as f64 / n as f64;
                vertices.push(
                    centre
                        + r * DVec3::new(
                            theta.sin() * phi.cos(),
                            theta.sin() * phi.sin(),
                            theta.cos(),
                        ),
                );
            }
        }
        let at = |i: usize, j: usize| (2 + (i - 1) * n + j % n) as u32;
        let mut triangles = Vec::new();
        for j in 0..n {
            triangles.push([0, at(1, j), at(1, j + 1)]);
            triangles.push([1, at(rings - 1, j + 1), at(rings - 1, j)]);
        }
        for i in 1..rings - 1 {
            for j in 0..n {
                triangles.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
                triangles.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
        Self {
            vertices,
            triangles,
        }
    }

    /// A torus about `centre` in the `xy` plane: tube radius `r` about a circle of radius `big`,
    /// `n` segments around the circle and `m` around the tube, outward.
    pub fn torus(centre: DVec3, big: f64, r: f64, n: usize, m: usize) -> Self {
        let (n, m) = (n.max(3), m.max(3));
        let tau = 2.0 * std::f64::consts::PI;
        let mut vertices = Vec::with_capacity(n * m);
        for i in 0..n {
            let u = tau * i as f64 / n as f64;
            for j in 0..m {
                let v = tau * j as f64 / m as f64;
                let rr = big + r * v.cos();
                vertices.push(centre + DVec3::new(rr * u.cos(), rr * u.sin(), r * v.sin()));
            }
        }
        let at = |i: usize, j: usize| ((i % n) * m + j % m) as u32;
        let mut triangles = Vec::with_capacity(2 * n * m);
        for i in 0..n {
            for j in 0..m {
                triangles.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
                triangles.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
        Self {
            vertices,
            triangles,
        }
    }
}

/// What repairing a mesh found and did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MeshStats {
    /// Triangles read.
    pub triangles_read: usize,
    /// Triangles kept.
    pub triangles: usize,
    /// Dropped: zero-area triangles (or with a repeated vertex).
    pub degenerate: usize,
    /// Dropped: copies of a triangle already present (same three vertices).
    pub duplicates: usize,
    /// Turned over to agree with their neighbours (or their whole part turned inside out).
    pub flipped: usize,
    /// Edges with one triangle: the rims of holes (0 for a closed surface).
    pub boundary_edges: usize,
    /// Edges with more than two triangles.
    pub non_manifold_edges: usize,
}

impl TriMesh {
    /// Repairs the mesh for filling: welds vertices at the same position, drops zero-area and
    /// duplicated triangles, turns each connected part's triangles to agree with their
    /// neighbours across manifold edges, and each closed part outward (positive volume).
    /// Holes and non-manifold edges are counted, not closed: the winding number bridges small
    /// holes.
    pub fn repaired(&self) -> (TriMesh, MeshStats) {
        let mut stats = MeshStats {
            triangles_read: self.triangles.len(),
            ..Default::default()
        };
        // Weld bit-identical positions (STL repeats every vertex per facet).
        let mut weld: HashMap<[u64; 3], u32> = HashMap::new();
        let mut vertices = Vec::new();
        let remap: Vec<u32> = self
            .vertices
            .iter()
            .map(|v| {
                let key = [v.x, v.y, v.z].map(|c| (c + 0.0).to_bits());
                *weld.entry(key).or_insert_with(|| {
                    vertices.push(*v);
                    vertices.len() as u32 - 1
                })
            })
            .collect();
        let scale = self
            .bounds()
            .map(|(lo, hi)| (hi - lo).length())
            .unwrap_or(0.0);
        let min_area2 = (1e-12 * scale * scale).powi(2);
        let mut seen = std::collections::HashSet::new();
        let mut triangles = Vec::with_capacity(self.triangles.len());
        for t in &self.triangles {
            let t = t.map(|i| remap[i as usize]);
            let [a, b, c] = t.map(|i| vertices[i as usize]);
            if t[0] == t[1]
                || t[1] == t[2]
                || t[0] == t[2]
                || (b - a).cross(c - a).length_squared() <= min_area2
            {
                stats.degenerate += 1;
                continue;
            }
            let mut key = t;
            key.sort_unstable();
            if !seen.insert(key) {
                stats.duplicates += 1;
                continue;
            }
            triangles.push(t);
        }
        // Edges: (low, high) -> triangles using them.
        let mut edges: HashMap<(u32, u32), Vec<u32>> = HashMap::new();
        for (k, t) in triangles.iter().enumerate() {
            for e in 0..3 {
                let (a, b) = (t[e], t[(e + 1) % 3]);
                edges
                    .entry((a.min(b), a.max(b)))
                    .or_default()
                    .push(k as u32);
            }
        }
        for users in edges.values() {
            match users.len() {
                1 => stats.boundary_edges += 1,
                2 => {}
                _ => stats.non_manifold_edges += 1,
            }
        }
        // Consistent orientation: breadth-first over manifold edges; a neighbour that runs
        // the shared edge in the same direction is turned over.
        let directed =
            |t: &[u32; 3], a: u32, b: u32| (0..3).any(|e| t[e] == a && t[(e + 1) % 3] == b);
        let mut part = vec![u32::MAX; triangles.len()];
        let mut parts = 0u32;
        for seed in 0..triangles.len() {
            if part[seed] != u32::MAX {
                continue;
            }
            part[seed] = parts;
            let mut queue = std::collections::VecDeque::from([seed]);
            while let Some(k) = queue.pop_front() {
                let t = triangles[k];
                for e in 0..3 {
                    let (a, b) = (t[e], t[(e + 1) % 3]);
                    let users = &edges[&(a.min(b), a.max(b))];
                    if users.len() != 2 {
                        continue;
                    }
                    let other = if users[0] as usize == k {
                        users[1]
                    } else {
                        users[0]
                    } as usize;
                    if part[other] != u32::MAX {
                        continue;
                    }
                    part[other] = parts;
                    if directed(&triangles[other], a, b) {
                        triangles[other].swap(1, 2);
                        stats.flipped += 1;
                    }
                    queue.push_back(other);
                }
            }
            parts += 1;
        }
        // Each part outward: its signed volume about the mesh's centre positive.
        let centre = self
            .bounds()
            .map(|(lo, hi)| 0.5 * (lo + hi))
            .unwrap_or(DVec3::ZERO);
        let mut volume = vec![0.0; parts as usize];
        for (k, t) in triangles.iter().enumerate() {
            let [a, b, c] = t.map(|i| vertices[i as usize] - centre);
            volume[part[k] as usize] += a.dot(b.cross(c));
        }
        for (k, t) in triangles.iter_mut().enumerate() {
            if volume[part[k] as usize] < 0.0 {
                t.swap(1, 2);
                stats.flipped += 1;
            }
        }
        stats.triangles = triangles.len();
        (
            TriMesh {
                vertices,
                triangles,
            },
            stats,
        )
    }
}

/// A solid bounded by a triangle mesh: inside where the generalized winding number is at least
/// ½ (so small holes, duplicated and flipped triangles do not break it), with the distance to
/// the surface for the body-fitting relaxation.
#[derive(Clone, Debug)]
pub struct MeshSolid {
    name: String,
    mesh: TriMesh,
    stats: MeshStats,
    bvh: Bvh,
    normals: Vec<DVec3>,
    bounds: (DVec3, DVec3),
    volume: f64,
}

impl MeshSolid {
    /// The solid of `mesh` (repaired first, [`TriMesh::repaired`]); `name` (the file) names it
    /// in errors.
    ///
    /// # Errors
    /// A mesh with no triangle of positive area, or one that encloses no volume (an open
    /// sheet: its boundary edges counted in the message).
    pub fn new(mesh: TriMesh, name: &str) -> Result<Self, Error> {
        let (mesh, stats) = mesh.repaired();
        if mesh.triangles.is_empty() {
            return Err(file_error(
                name,
                format!(
                    "no triangle of positive area to fill ({} read, {} degenerate)",
                    stats.triangles_read, stats.degenerate
                ),
            ));
        }
        let corners = mesh.corners();
        let bvh = Bvh::new(&corners);
        let normals = corners
            .iter()
            .map(|[a, b, c]| (*b - *a).cross(*c - *a).normalize_or_zero())
            .collect();
        let bounds = mesh.bounds().expect("triangles");
        let volume = mesh.volume();
        let size = (bounds.1 - bounds.0).max_element();
        // An open sheet encloses nothing: its volume about the centre is ~0 relative to its
        // bounding box (a closed surface of any shape encloses a fair fraction of it).
        if volume.is_nan() || volume <= 1e-9 * size.powi(3) {
            return Err(file_error(
                name,
                format!(
                    "the surface encloses no volume ({} triangles, {} boundary edges): an open sheet cannot be filled",
                    stats.triangles, stats.boundary_edges
                ),
            ));
        }
        Ok(Self {
            name: name.into(),
            mesh,
            stats,
            bvh,
            normals,
            bounds,
            volume,
        })
    }

    /// Reads `path` ([`TriMesh::read`]), places it and makes the solid.
    pub fn read(path: &Path, placement: &Placement) -> Result<Self, Error> {
        placement.validate()?;
        let name = path.display().to_string();
        Self::new(TriMesh::read(path)?.placed(placement), &name)
    }

    /// The enclosed volume of the repaired mesh ([`TriMesh::volume`]).
    pub fn volume(&self) -> f64 {
        self.volume
    }

    /// The repaired mesh.
    pub fn mesh(&self) -> &TriMesh {
        &self.mesh
    }

    /// What the repair found.
    pub fn stats(&self) -> MeshStats {
        self.stats
    }

    /// The generalized winding number at `x` (1 inside, 0 outside a closed surface).
    pub fn winding_number(&self, x: DVec3) -> f64 {
        self.bvh.winding_number(x)
    }

    /// The distance from `x` to the surface and the closest surface point.
    pub fn closest(&self, x: DVec3) -> (f64, DVec3) {
        let (d2, p, _) = self.bvh.closest(x);
        (d2.sqrt(), p)
    }
}

impl Shape<D3> for MeshSolid {
    fn contains(&self, x: DVec3) -> bool {
        // Outside the bounds the winding number is small but not exactly 0; skip the query.
        x.cmpge(self.bounds.0).all()
            && x.cmple(self.bounds.1).all()
            && self.winding_number(x) >= 0.5
    }

    fn bounds(&self) -> (DVec3, DVec3) {
        self.bounds
    }
}

impl Boundary<D3> for MeshSolid {
    fn signed_distance(&self, x: DVec3) -> (f64, DVec3) {
        self.signed_distance_on_side(x, self.contains(x))
    }

    fn signed_distance_on_side(&self, x: DVec3, inside: bool) -> (f64, DVec3) {
        let (d2, p, t) = self.bvh.closest(x);
        let d = d2.sqrt();
        let face = self.normals[t as usize];
        let n = if d > 1e-9 * (self.bounds.1 - self.bounds.0).max_element() {
            let away = (x - p) / d;
            if inside {
                -away
            } else {
                away
            }
        } else {
            face
        };
        (if inside { -d } else { d }, n)
    }

    fn volume(&self) -> f64 {
        self.volume
    }

    fn name(&self) -> &str {
        &self.name
    }
}
