//! # chrono-fea
//!
//! Finite elements for chrono-rs. This first part (issue 7) has the gradient-deficient
//! ANCF cable/beam element (Gerstmayr & Shabana 2006), meshes of it with supports and
//! loads, a static solver (Newton with load stepping, faer sparse LU) and a modal
//! analysis; the analytic references of the beam benchmarks are in [`analytic`].
//!
//! A mesh steps in a [`System`](chrono_core::System) as a
//! [`PhysicsItem`](chrono_core::item::PhysicsItem) ([`CableItem`], module [`dynamics`]):
//! linearized implicit Euler with the iteration matrix `M + h R + h^2 K` as the coupled
//! mass operator of the CCP ([`SparseSpd`], faer sparse Cholesky), nodes attached to
//! fixed points or rigid bodies by bilateral rows, nodes (and optionally element
//! midpoints) as contact spheres against the rigid bodies' colliders.
//!
//! Solids: the linear 4-node tetrahedron with the St. Venant–Kirchhoff material
//! ([`Tet4`], [`SolidMaterial`]), meshes of it ([`TetMesh`]) with supports, prescribed
//! displacements, nodal forces, face tractions and gravity, structured box meshes with
//! their face node sets ([`BoxMesh`]), solved by the same Newton solver
//! ([`solve_static`], any [`StaticModel`]), their natural frequencies
//! ([`natural_frequencies`]), and stepped implicitly in a system like the cable
//! ([`TetItem`]: supports, attachment rows, surface-node contact spheres).
//!
//! Shells: the ANCF 4-node shell of Yamashita et al. (2015) with ANS and EAS locking
//! remedies, a curved reference configuration and a follower pressure ([`AncfShell`],
//! [`ShellMaterial`]), meshes of it ([`ShellMesh`]: plates, parametric grids, a sphere
//! octant; [`TireMesh`]: an open torus cut at the rim) solved statically by the same
//! Newton solver (with gravity, [`ShellMesh::set_gravity`]) and stepped in a system
//! ([`ShellItem`]: gravity, follower pressure with its symmetrized load stiffness,
//! stiffness-proportional damping, attachment rows, node contact spheres). The three
//! items share their block bookkeeping (module `implicit`).
//!
//! Beams with torsion: the fully parameterized ANCF beam (nodes `[r, r_x, r_y, r_z]`,
//! structural-mechanics strains, shear and section strains sampled at the nodes against
//! locking, curved stress-free reference configurations; [`AncfBeam`], [`BeamSection`]),
//! meshes of it ([`BeamMesh`]: straight, arcs, clamps, forces, couples, gravity), solved
//! by the same Newton solver (the 45-degree bend of Bathe & Bolourchi 1979).
//!
//! A cable node's slope can be kept along a direction of a rigid body
//! ([`CableItem::attach_slope`], module [`slope_attach`]): with a position attachment, a
//! clamp of the cable to the body, its bending moment carried by CCP rows.
//!
//! Output: the deformed meshes with their strain and stress fields as VTK unstructured
//! grids for ParaView (module [`vtk`]).
//!
//! Still to come (see the issue): the fully parameterized beam in the dynamic (CCP)
//! stepper.
//!
//! ```
//! use chrono_fea::{BeamMaterial, CableMesh, CableQuadrature, NodeId, StaticSettings, solve_static};
//! use nalgebra::Vector3;
//!
//! let mat = BeamMaterial::rectangle(2e11, 7850.0, 0.01, 0.01, 0.0)?;
//! let mut mesh = CableMesh::straight(Vector3::zeros(), Vector3::x(), 8, mat, CableQuadrature::default())?;
//! mesh.clamp(NodeId(0))?;
//! mesh.set_force(NodeId(8), Vector3::new(0.0, 0.0, -1.0))?;
//! solve_static(&mut mesh, &StaticSettings { load_steps: 1, ..Default::default() })?;
//! let tip = mesh.node(NodeId(8))?.displacement();
//! let exact = 1.0 / (3.0 * mat.bending_stiffness()); // P L^3 / (3 E I)
//! assert!((-tip.z / exact - 1.0).abs() < 1e-3);
//! # Ok::<(), chrono_fea::FeaError>(())
//! ```

pub mod analytic;
mod attach_rows;
pub mod beam_mesh;
pub mod cantilever;
pub mod dynamics;
pub mod element;
pub mod error;
mod implicit;
pub mod material;
pub mod mesh;
pub mod modal;
pub mod node;
pub mod quadrature;
pub mod shell_dynamics;
pub mod shell_mesh;
pub mod slope_attach;
pub mod spd;
pub mod statics;
pub mod tet_box;
pub mod tet_dynamics;
pub mod tet_mesh;
pub mod tire_mesh;
pub mod tire_mount;
pub mod tire_static;
pub mod vtk;

pub use beam_mesh::BeamMesh;
pub use cantilever::{beam_cantilever, cable_cantilever};
pub use dynamics::{AttachTarget, Attachment, CableItem};
pub use element::{
    AncfBeam, AncfCable, AncfShell, BeamQuadrature, CableQuadrature, ShellLocking, ShellMaterial,
    Tet4, von_mises,
};
pub use error::{FeaError, Result};
pub use material::{BeamMaterial, BeamSection, SolidMaterial, SolidModel};
pub use mesh::{CableMesh, DofMap};
pub use modal::{MassModel, natural_frequencies};
pub use node::{BeamNode, GradientNode, NodeId, SolidNode};
pub use shell_dynamics::{DirectorTarget, ShellItem};
pub use shell_mesh::ShellMesh;
pub use slope_attach::{SlopeAttachment, SlopeTarget};
pub use spd::SparseSpd;
pub use statics::{StaticModel, StaticReport, StaticSettings, solve_static};
pub use tet_box::{BoxFaces, BoxMesh, HexSplit};
pub use tet_dynamics::TetItem;
pub use tet_mesh::TetMesh;
pub use tire_mesh::{TireGeometry, TireMesh};
pub use tire_mount::{BeadMount, InflatedTire, mount_on_rim, mount_on_rim_at};
pub use tire_static::{StaticPress, TireOnGround, check_fits_rim};
