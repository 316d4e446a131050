//! A tire-like toroidal shell: an open torus of ANCF shell elements cut at the rim, with
//! its two bead rings.
//!
//! The carcass is the surface of revolution of a circular arc of radius `a` (the section
//! radius) whose centre lies at the distance `R_c` (the ring radius) from the axle. The
//! axle is the `Y` axis through `centre`; with the angle `theta` around the axle and the
//! angle `phi` across the section, measured from the tread (the outermost point),
//!
//! ```text
//! e_r(theta) = (cos theta, 0, sin theta),      n(theta, phi) = cos phi e_r + sin phi e_y
//! X(theta, phi) = centre + R_c e_r + a n,       phi in [-phi_b, phi_b]
//! ```
//!
//! `n` is the outward unit normal (the directors), `phi_b` the bead angle: the arc stops
//! at the two bead rings `phi = +-phi_b`, where a tire sits on its rim, and the rim
//! (not modelled by the mesh; a rigid body) closes the cavity. The outer radius is
//! `R_c + a`, the section width `2 a` (for `phi_b >= pi/2`), the rim width
//! `2 a sin phi_b`.
//!
//! Why open and not closed: a tire is an open shell clamped or hinged at its beads, and
//! the bead rings are where the attachments to the rim go. The inflation pressure
//! ([`ShellMesh::set_pressure`], `p > 0` outward) on the open surface is still balanced:
//! the resultant of a uniform pressure on a surface is `p` times its vector area, which
//! only depends on its boundary (`1/2 oint x dx`, also exactly for the bilinear elements,
//! whose shape functions sum to 1). The two bead rings are planar circles of opposite
//! orientation: as long as they move with the rim, the net pressure force on the tire
//! is zero, however the carcass deforms.
//!
//! Mesh: `n_around` elements around (periodic: the seam at `theta = 0` is shared) times
//! `n_across` across the arc, nodes `(i, j)` with `theta_i = 2 pi i / n_around`,
//! `phi_j = -phi_b + 2 phi_b j / n_across`, numbered `NodeId(i (n_across + 1) + j)`;
//! elements counter-clockwise about the outward directors.

use nalgebra::Vector3;

use crate::element::ShellMaterial;
use crate::error::{FeaError, Result, finite3, positive};
use crate::node::NodeId;
use crate::shell_mesh::ShellMesh;

/// Geometry of a toroidal tire carcass (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TireGeometry {
    /// Centre of the wheel (on the axle), m.
    pub centre: Vector3<f64>,
    /// Ring radius `R_c`: axle to section centre, m.
    pub ring_radius: f64,
    /// Section radius `a` of the mid surface, m (`a < R_c`).
    pub section_radius: f64,
    /// Bead angle `phi_b`, rad, in `(0, pi)`: half the angle of the section arc.
    pub bead_angle: f64,
    /// Elements around the axle (>= 3).
    pub n_around: usize,
    /// Elements across the section arc (>= 1).
    pub n_across: usize,
    /// Shell thickness, m.
    pub thickness: f64,
}

impl TireGeometry {
    /// Outer radius of the mid surface `R_c + a`, m.
    pub fn outer_radius(&self) -> f64 {
        self.ring_radius + self.section_radius
    }

    /// Position and outward normal at `(theta, phi)` of the reference surface.
    pub fn surface(&self, theta: f64, phi: f64) -> (Vector3<f64>, Vector3<f64>) {
        let er = Vector3::new(theta.cos(), 0.0, theta.sin());
        let n = phi.cos() * er + phi.sin() * Vector3::y();
        (
            self.centre + self.ring_radius * er + self.section_radius * n,
            n,
        )
    }

    fn validate(&self) -> Result<()> {
        finite3("tire.centre", &self.centre)?;
        let rc = positive("tire.ring_radius", self.ring_radius)?;
        let a = positive("tire.section_radius", self.section_radius)?;
        if a >= rc {
            return Err(FeaError::invalid(
                "tire.section_radius",
                a,
                format!("must be < the ring radius {rc} (a torus, not a spindle)"),
            ));
        }
        let b = self.bead_angle;
        if !(b.is_finite() && b > 0.0 && b < std::f64::consts::PI) {
            return Err(FeaError::invalid(
                "tire.bead_angle",
                b,
                "must be in (0, pi) rad",
            ));
        }
        if self.n_around < 3 {
            return Err(FeaError::invalid(
                "tire.n_around",
                self.n_around,
                "must be >= 3",
            ));
        }
        if self.n_across == 0 {
            return Err(FeaError::invalid("tire.n_across", 0, "must be >= 1"));
        }
        positive("section.thickness", self.thickness)?;
        Ok(())
    }
}

/// The mesh of a [`TireGeometry`] and its node rings.
#[derive(Debug, Clone)]
pub struct TireMesh {
    /// The shell mesh.
    pub mesh: ShellMesh,
    /// The bead rings `phi = -phi_b` and `phi = +phi_b`, each `n_around` nodes in the
    /// order of `theta`.
    pub beads: [Vec<NodeId>; 2],
    /// The geometry it was built from.
    pub geometry: TireGeometry,
}

impl TireMesh {
    /// Build the open torus of `geometry` with `material` (module docs). Errors name the
    /// field and value.
    pub fn new(geometry: TireGeometry, material: ShellMaterial) -> Result<Self> {
        geometry.validate()?;
        let (na, nc) = (geometry.n_around, geometry.n_across);
        let mut mesh = ShellMesh::new();
        for i in 0..na {
            let theta = std::f64::consts::TAU * i as f64 / na as f64;
            for j in 0..=nc {
                let phi = geometry.bead_angle * (2.0 * j as f64 / nc as f64 - 1.0);
                let (x, n) = geometry.surface(theta, phi);
                mesh.add_node(x, n)?;
            }
        }
        // X_phi x X_theta points along +n: (phi, theta) is the counter-clockwise order.
        for i in 0..na {
            for j in 0..nc {
                let i1 = (i + 1) % na;
                mesh.add_element(
                    [
                        Self::node(&geometry, i, j),
                        Self::node(&geometry, i, j + 1),
                        Self::node(&geometry, i1, j + 1),
                        Self::node(&geometry, i1, j),
                    ],
                    geometry.thickness,
                    material,
                )?;
            }
        }
        let ring = |j: usize| (0..na).map(|i| Self::node(&geometry, i, j)).collect();
        Ok(Self {
            mesh,
            beads: [ring(0), ring(nc)],
            geometry,
        })
    }

    /// Node `(i, j)`: `i`-th around (mod `n_around`), `j`-th across (`0..=n_across`).
    pub fn node(geometry: &TireGeometry, i: usize, j: usize) -> NodeId {
        NodeId((i % geometry.n_around) * (geometry.n_across + 1) + j)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn geometry() -> TireGeometry {
        TireGeometry {
            centre: Vector3::new(0.1, 0.2, 0.3),
            ring_radius: 0.3,
            section_radius: 0.08,
            bead_angle: 0.75 * std::f64::consts::PI,
            n_around: 24,
            n_across: 8,
            thickness: 0.004,
        }
    }

    /// The mesh area converges to the surface of revolution's: by Pappus,
    /// `A = 2 pi int (R_c + a cos phi) a dphi = 4 pi a (R_c phi_b + a sin phi_b)`;
    /// bilinear facets inscribed in the surface are smaller by `O(h^2)`.
    #[test]
    fn area_converges_to_pappus() {
        let g = geometry();
        let exact = 4.0
            * std::f64::consts::PI
            * g.section_radius
            * (g.ring_radius * g.bead_angle + g.section_radius * g.bead_angle.sin());
        let m = ShellMaterial::isotropic(1e8, 0.3, 1000.0).unwrap();
        let mut errs = Vec::new();
        for k in [1, 2] {
            let gk = TireGeometry {
                n_around: g.n_around * k,
                n_across: g.n_across * k,
                ..g
            };
            let t = TireMesh::new(gk, m).unwrap();
            assert_eq!(t.mesh.nodes().len(), gk.n_around * (gk.n_across + 1));
            assert_eq!(t.beads[0].len(), gk.n_around);
            errs.push((exact - t.mesh.area()) / exact);
        }
        assert!(errs[0] > 0.0 && errs[0] < 0.05, "{errs:?}");
        let ratio = errs[0] / errs[1];
        assert!((ratio - 4.0).abs() < 0.2, "second order: {errs:?}");
    }

    #[test]
    fn bad_geometry_names_the_field() {
        let m = ShellMaterial::isotropic(1e8, 0.3, 1000.0).unwrap();
        for (g, field) in [
            (
                TireGeometry {
                    bead_angle: 4.0,
                    ..geometry()
                },
                "tire.bead_angle",
            ),
            (
                TireGeometry {
                    section_radius: 0.5,
                    ..geometry()
                },
                "tire.section_radius",
            ),
            (
                TireGeometry {
                    n_around: 2,
                    ..geometry()
                },
                "tire.n_around",
            ),
        ] {
            let e = TireMesh::new(g, m).unwrap_err().to_string();
            assert!(e.contains(field), "{e}");
        }
    }
}
