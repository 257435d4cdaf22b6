//! # sph-geometry
//!
//! Where particles come from: shapes and the lattice and polar generators ([`generate`]),
//! triangle meshes read from STL and OBJ files ([`mesh`]), 2D outlines read from vertex lists
//! and SVG drawings ([`outline`]), and body-fitted particles: a lattice fill relaxed onto the
//! surface, with a report of how well it fits ([`fit`]).
//!
//! Every method (TL, UL, MPS; 2D and 3D) starts from the [`generate::ParticleSet`] made here,
//! turned into a [`sph_core::Body`] by `Body::from(set)`.
//!
//! From a mesh file to the particles of a body in a few lines:
//!
//! ```
//! use sph_geometry::fit::{fit, FitOptions};
//! use sph_geometry::mesh::{MeshSolid, Placement, TriMesh};
//! use sph_geometry::glam::DVec3;
//! use sph_core::Body;
//!
//! # let dir = std::env::temp_dir().join(format!("sph-geometry-doc-{}", std::process::id()));
//! # std::fs::create_dir_all(&dir).unwrap();
//! # let path = dir.join("part.stl");
//! # TriMesh::uv_sphere(DVec3::ZERO, 5.0, 32).write_stl(&path)?;
//! // A part drawn in millimetres, placed 1 cm up, fitted at 1 mm spacing.
//! let place = Placement { scale: 1e-3, translate: DVec3::new(0.0, 0.0, 0.01), ..Default::default() };
//! let part = MeshSolid::read(&path, &place)?;
//! let (set, report) = fit(&part, 1e-3, &FitOptions { relax_steps: 20, ..FitOptions::default() })?;
//! assert_eq!(report.particles, set.len());
//! assert!((report.volume / report.mesh_volume - 1.0).abs() < 0.1);
//! let body = Body::from(set);
//! # std::fs::remove_dir_all(&dir).ok();
//! # let _ = body;
//! # Ok::<(), sph_core::Error>(())
//! ```
#![deny(missing_docs)]
// Per-axis loops index several small arrays at once; iterator chains would obscure them.
#![allow(clippy::needless_range_loop)]

/// glam, whose vectors every API here takes.
pub use glam;

mod bvh;
pub mod count;
pub mod fit;
pub mod generate;
pub mod mesh;
pub mod outline;

use generate::{ParticleSet, Shape};
use sph_core::{Body, Dim, Error};

/// A region with a surface: a [`Shape`] that also knows its signed distance (what the
/// body-fitting relaxation and its report need), its enclosed volume and the name (file) that
/// errors quote. Implemented by [`mesh::MeshSolid`] (3D) and [`outline::OutlineSolid`] (2D).
pub trait Boundary<D: Dim>: Shape<D> {
    /// The signed distance from `x` to the surface (negative inside) and the outward unit
    /// normal at the closest surface point.
    fn signed_distance(&self, x: D::Vector) -> (f64, D::Vector);

    /// [`Self::signed_distance`] of a point whose side is known (`inside`): one that was
    /// measured at some distance from the surface and has moved less than that distance since.
    /// The same result without the inside test, which dominates the cost on a large mesh (a
    /// winding number against a closest point). The default ignores the hint.
    fn signed_distance_on_side(&self, x: D::Vector, inside: bool) -> (f64, D::Vector) {
        let _ = inside;
        self.signed_distance(x)
    }

    /// The enclosed volume (area in 2D).
    fn volume(&self) -> f64;

    /// The name errors quote (the file it was read from).
    fn name(&self) -> &str;
}

/// A mesh solid is a tool surface ([`sph_core::tool::ToolShape::Surface`]): its signed
/// distance ([`Boundary::signed_distance`]: the closest point by the BVH, the side by the
/// generalized winding number) and bounds.
impl sph_core::tool::SignedDistance<sph_core::D3> for mesh::MeshSolid {
    fn signed_distance(&self, x: glam::DVec3) -> (f64, glam::DVec3) {
        Boundary::<sph_core::D3>::signed_distance(self, x)
    }

    fn bounds(&self) -> (glam::DVec3, glam::DVec3) {
        Shape::<sph_core::D3>::bounds(self)
    }
}

/// An outline region is a 2D tool surface ([`sph_core::tool::ToolShape::Surface`]).
impl sph_core::tool::SignedDistance<sph_core::D2> for outline::OutlineSolid {
    fn signed_distance(&self, x: glam::DVec2) -> (f64, glam::DVec2) {
        Boundary::<sph_core::D2>::signed_distance(self, x)
    }

    fn bounds(&self) -> (glam::DVec2, glam::DVec2) {
        Shape::<sph_core::D2>::bounds(self)
    }
}

/// A mesh or outline file is a tool surface of its dimension
/// ([`sph_core::tool::ToolShape::Surface`]; what scene files build for a `[[tool]]` whose
/// shape is `mesh = { … }` or `outline = { … }`).
impl<D: Dim> sph_core::tool::SignedDistance<D> for FileSolid<D> {
    fn signed_distance(&self, x: D::Vector) -> (f64, D::Vector) {
        Boundary::<D>::signed_distance(self, x)
    }

    fn bounds(&self) -> (D::Vector, D::Vector) {
        Shape::<D>::bounds(self)
    }
}

impl<D: Dim> FileSolid<D> {
    /// This solid as a rigid tool's shape ([`sph_core::tool::ToolShape::Surface`]).
    ///
    /// # Errors
    /// Bounds that are not finite ([`sph_core::tool::ToolShape::surface`]).
    pub fn into_tool_shape(self) -> Result<sph_core::tool::ToolShape<D>, Error> {
        sph_core::tool::ToolShape::surface(std::sync::Arc::new(self))
    }
}

/// A one-line error about the geometry file `file`.
pub(crate) fn file_error(file: &str, message: impl std::fmt::Display) -> Error {
    Error::Geometry {
        file: file.to_string(),
        message: message.to_string(),
    }
}

impl<D: Dim> ParticleSet<D> {
    /// The body of this set with spacing `dp` (regions dropped: read them first).
    pub fn into_body(self, dp: f64) -> Body<D> {
        let (positions, volumes, _) = self.into_parts();
        Body::new(positions, volumes, dp)
    }
}

/// A generated set becomes a body with the spacing its generator used
/// ([`ParticleSet::spacing`]), or, for a set assembled from parts, `(mean volume)^(1/d)`.
impl<D: Dim> From<ParticleSet<D>> for Body<D> {
    fn from(set: ParticleSet<D>) -> Self {
        let dp = set.spacing().unwrap_or_else(|| {
            let n = set.len().max(1) as f64;
            (set.total_volume() / n).powf(1.0 / D::D as f64)
        });
        set.into_body(dp)
    }
}

/// A mesh (3D) or an outline (2D) read from a file, as a [`Shape`] and [`Boundary`] of the
/// dimension `D` a scene is written in (what scene files build for `mesh = { … }` and
/// `outline = { … }`).
#[derive(Clone, Debug)]
pub struct FileSolid<D: Dim> {
    inner: FileSolidKind,
    _dim: std::marker::PhantomData<D>,
}

#[derive(Clone, Debug)]
enum FileSolidKind {
    Mesh(mesh::MeshSolid),
    Outline(outline::OutlineSolid),
}

impl<D: Dim> FileSolid<D> {
    /// The solid of a mesh file ([`mesh::MeshSolid::read`]); errors unless `D` is 3D.
    pub fn mesh(path: &std::path::Path, placement: &mesh::Placement) -> Result<Self, Error> {
        if D::D != 3 {
            return Err(file_error(
                &path.display().to_string(),
                "a mesh is a 3D shape (in 2D use an outline)",
            ));
        }
        Ok(Self {
            inner: FileSolidKind::Mesh(mesh::MeshSolid::read(path, placement)?),
            _dim: std::marker::PhantomData,
        })
    }

    /// The region of an outline file ([`outline::OutlineSolid::read`]); errors unless `D` is 2D.
    pub fn outline(path: &std::path::Path, placement: &mesh::Placement) -> Result<Self, Error> {
        if D::D != 2 {
            return Err(file_error(
                &path.display().to_string(),
                "an outline is a 2D shape (in 3D use a mesh)",
            ));
        }
        Ok(Self {
            inner: FileSolidKind::Outline(outline::OutlineSolid::read(path, placement)?),
            _dim: std::marker::PhantomData,
        })
    }

    fn to_d(v: glam::DVec3) -> D::Vector {
        D::vector([v.x, v.y, v.z])
    }
}

impl<D: Dim> Shape<D> for FileSolid<D> {
    fn contains(&self, x: D::Vector) -> bool {
        let x = D::to_vec3(x);
        match &self.inner {
            FileSolidKind::Mesh(m) => m.contains(x),
            FileSolidKind::Outline(o) => o.contains(x.truncate()),
        }
    }

    fn bounds(&self) -> (D::Vector, D::Vector) {
        match &self.inner {
            FileSolidKind::Mesh(m) => {
                let (lo, hi) = Shape::<sph_core::D3>::bounds(m);
                (Self::to_d(lo), Self::to_d(hi))
            }
            FileSolidKind::Outline(o) => {
                let (lo, hi) = Shape::<sph_core::D2>::bounds(o);
                (Self::to_d(lo.extend(0.0)), Self::to_d(hi.extend(0.0)))
            }
        }
    }
}

impl<D: Dim> Boundary<D> for FileSolid<D> {
    fn signed_distance(&self, x: D::Vector) -> (f64, D::Vector) {
        let x = D::to_vec3(x);
        match &self.inner {
            FileSolidKind::Mesh(m) => {
                let (d, n) = Boundary::<sph_core::D3>::signed_distance(m, x);
                (d, Self::to_d(n))
            }
            FileSolidKind::Outline(o) => {
                let (d, n) = o.signed_distance(x.truncate());
                (d, Self::to_d(n.extend(0.0)))
            }
        }
    }

    fn signed_distance_on_side(&self, x: D::Vector, inside: bool) -> (f64, D::Vector) {
        let x = D::to_vec3(x);
        match &self.inner {
            FileSolidKind::Mesh(m) => {
                let (d, n) = Boundary::<sph_core::D3>::signed_distance_on_side(m, x, inside);
                (d, Self::to_d(n))
            }
            FileSolidKind::Outline(o) => {
                let (d, n) = o.signed_distance_on_side(x.truncate(), inside);
                (d, Self::to_d(n.extend(0.0)))
            }
        }
    }

    fn volume(&self) -> f64 {
        match &self.inner {
            FileSolidKind::Mesh(m) => Boundary::<sph_core::D3>::volume(m),
            FileSolidKind::Outline(o) => o.area(),
        }
    }

    fn name(&self) -> &str {
        match &self.inner {
            FileSolidKind::Mesh(m) => Boundary::<sph_core::D3>::name(m),
            FileSolidKind::Outline(o) => Boundary::<sph_core::D2>::name(o),
        }
    }
}
