//! An inflated tire on its rim pressed onto flat rigid ground: the static load–deflection
//! curve by Newton's method with an active set of contact nodes.
//!
//! # The problem
//!
//! The rim is rigid and moves straight down by the deflection `delta` from the position
//! where the inflated tire just touches the ground (displacement control): its bead nodes
//! are held at their inflated positions minus `delta e_z` ([`BeadMount::Hinged`]: the
//! positions; [`BeadMount::Clamped`]: the directors too). The ground is the plane on which
//! the node spheres of radius `t / 2` rest (the outer face of the shell, as in the
//! dynamic tire, [`ShellItem::set_contact_spheres`](crate::ShellItem::set_contact_spheres)):
//! a node in contact has `z = z_g + t / 2` and is free in `x, y` (frictionless). With the
//! inflation pressure as a follower load and no gravity (the carcass weighs about 0.3 % of
//! the loads of interest), equilibrium is
//!
//! ```text
//! Q(q) - F_p(q) = f_c,     f_c,n = lambda_n e_z  (nodes in contact),  0 elsewhere
//! lambda_n >= 0,   g_n = z_n - z_g - t/2 >= 0,   lambda_n g_n = 0
//! ```
//!
//! solved by the classical primal active-set loop (e.g. Wriggers, *Computational Contact
//! Mechanics*, 2nd ed., Springer 2006, sec. 6.3): Newton ([`solve_static`]) with the nodes
//! of the active set held at the ground, then the nodes that pull on the ground
//! (`lambda_n < 0`) released and the free nodes below it added, until the set does not
//! change. The load is the sum of the contact forces `W = sum lambda_n`, equal to the
//! force the rim exerts on the beads: the inflation pressure on the open carcass has no
//! resultant when its bead rings move rigidly (see [`TireMesh`]), which
//! [`StaticPress::bead_force`] checks.
//!
//! Load control ([`TireOnGround::press_to_load`]) finds `delta` with `W(delta) = W_target`
//! by the secant method on the monotone curve `W(delta)`, each evaluation continued from
//! the last solution.

use nalgebra::Vector3;

use crate::error::{FeaError, Result, positive};
use crate::node::NodeId;
use crate::shell_mesh::ShellMesh;
use crate::statics::{StaticSettings, solve_static};
use crate::tire_mesh::TireMesh;
use crate::tire_mount::{BeadMount, InflatedTire};

/// The static solution at one deflection ([`TireOnGround::press`]).
#[derive(Debug, Clone, PartialEq)]
pub struct StaticPress {
    /// Rim deflection from first touch, m.
    pub deflection: f64,
    /// Vertical load: the sum of the ground's contact forces, N.
    pub load: f64,
    /// The vertical force of the rim on the beads (the load carried through the beads,
    /// with the sign of a load pressing the rim down: `load` at equilibrium), N.
    pub bead_force: f64,
    /// Nodes in contact.
    pub nodes_in_contact: usize,
    /// Extent along `x` (the rolling direction) of the contact nodes, m: a lower bound on
    /// the patch length, quantized by the element length around.
    pub patch_length: f64,
    /// Extent along `y` (across) of the contact nodes, m.
    pub patch_width: f64,
    /// Active-set passes (Newton solves) of this deflection.
    pub passes: usize,
    /// Newton iterations over all passes.
    pub newton_iterations: usize,
}

/// An inflated tire on a rim above flat rigid ground (see the module docs).
#[derive(Debug, Clone)]
pub struct TireOnGround {
    /// The pressurized carcass, unsupported (reference configuration undeformed).
    base: ShellMesh,
    beads: Vec<NodeId>,
    mount: BeadMount,
    /// Inflated coordinates (all), the rim at first touch.
    inflated: Vec<f64>,
    /// Current coordinates: the last solution.
    q: Vec<f64>,
    /// Height of the node centres on the ground, m.
    z_contact: f64,
    active: Vec<bool>,
    deflection: f64,
    settings: StaticSettings,
}

/// Most active-set passes per deflection before giving up.
const MAX_PASSES: usize = 30;

impl TireOnGround {
    /// The tire `tire`, inflated as `inflated` says (its mount and pressure), its lowest
    /// node just touching the ground (the plane `z = min_n z_n - t/2`, `t` the thickness of
    /// the geometry). Errors: a mesh and inflation of different sizes.
    pub fn new(tire: &TireMesh, inflated: &InflatedTire, mount: BeadMount) -> Result<Self> {
        let q = inflated.inflated.coordinates();
        if q.len() != tire.mesh.ndof() {
            return Err(FeaError::invalid(
                "inflated.ndof",
                q.len(),
                format!("must equal the tire mesh's {}", tire.mesh.ndof()),
            ));
        }
        let z_contact = inflated.lowest_z();
        let n = tire.mesh.nodes().len();
        Ok(Self {
            base: inflated.mesh.clone(),
            beads: tire.beads.iter().flatten().copied().collect(),
            mount,
            inflated: q.clone(),
            q,
            z_contact,
            active: vec![false; n],
            deflection: 0.0,
            settings: StaticSettings {
                load_steps: 1,
                max_iterations: 40,
                relative_tolerance: 1e-9,
                absolute_tolerance: None,
            },
        })
    }

    /// The current configuration (all coordinates).
    pub fn coordinates(&self) -> &[f64] {
        &self.q
    }

    /// The current deflection, m.
    pub fn deflection(&self) -> f64 {
        self.deflection
    }

    /// The mesh at the current configuration (pressurized, unsupported).
    pub fn mesh(&self) -> Result<ShellMesh> {
        let mut m = self.base.clone();
        m.set_coordinates(&self.q)?;
        Ok(m)
    }

    /// Static equilibrium with the rim `deflection` (m, `>= 0`) below first touch, continued
    /// from the current solution (the whole tire first moved rigidly by the change).
    pub fn press(&mut self, deflection: f64) -> Result<StaticPress> {
        if !(deflection.is_finite() && deflection >= 0.0) {
            return Err(FeaError::invalid(
                "deflection",
                deflection,
                "must be finite and >= 0",
            ));
        }
        let n_nodes = self.active.len();
        let shift = deflection - self.deflection;
        for k in 0..n_nodes {
            self.q[6 * k + 2] -= shift;
        }
        let mut newton = 0;
        for pass in 1..=MAX_PASSES {
            let mut mesh = self.base.clone();
            // Nodes below the ground join the set before the solve (the predictor).
            for k in 0..n_nodes {
                if self.q[6 * k + 2] < self.z_contact {
                    self.active[k] = true;
                }
            }
            for &b in &self.beads {
                let k = b.0;
                for c in 0..6 {
                    self.q[6 * k + c] = self.inflated[6 * k + c];
                }
                self.q[6 * k + 2] -= deflection;
            }
            for k in (0..n_nodes).filter(|&k| self.active[k]) {
                self.q[6 * k + 2] = self.z_contact;
            }
            mesh.set_coordinates(&self.q)?;
            for &b in &self.beads {
                match self.mount {
                    BeadMount::Hinged => mesh.fix_position(b)?,
                    BeadMount::Clamped => mesh.fix_node(b)?,
                }
            }
            for k in (0..n_nodes).filter(|&k| self.active[k]) {
                mesh.fix_coordinate(NodeId(k), 2)?;
            }
            let report = solve_static(&mut mesh, &self.settings)?;
            newton += report.total_iterations();
            self.q = mesh.coordinates();
            let reaction = self.reactions(&mesh)?;
            let mut changed = false;
            for k in 0..n_nodes {
                let is_bead = self.beads.contains(&NodeId(k));
                if self.active[k] && !is_bead && reaction[6 * k + 2] < 0.0 {
                    self.active[k] = false;
                    changed = true;
                } else if !self.active[k] && self.q[6 * k + 2] < self.z_contact - 1e-12 {
                    changed = true;
                }
            }
            if !changed {
                self.deflection = deflection;
                return Ok(self.summary(&reaction, pass, newton));
            }
        }
        Err(FeaError::invalid(
            "deflection",
            deflection,
            format!("the contact set did not settle in {MAX_PASSES} active-set passes"),
        ))
    }

    /// `Q(q) - F_p(q)` at every coordinate: on a held coordinate, the force its support
    /// exerts on the mesh.
    fn reactions(&self, mesh: &ShellMesh) -> Result<Vec<f64>> {
        let map = mesh.dof_map();
        let (fint, _) = mesh.internal_force(&self.q, &map, false)?;
        let (fp, _) = mesh.pressure_force(&self.q, 1.0, &map, false)?;
        Ok(fint.iter().zip(&fp).map(|(a, b)| a - b).collect())
    }

    fn summary(&self, reaction: &[f64], passes: usize, newton: usize) -> StaticPress {
        let contact: Vec<usize> = (0..self.active.len())
            .filter(|&k| self.active[k] && !self.beads.contains(&NodeId(k)))
            .collect();
        let load = contact.iter().map(|&k| reaction[6 * k + 2]).sum();
        let bead_force = -self
            .beads
            .iter()
            .map(|b| reaction[6 * b.0 + 2])
            .sum::<f64>();
        let extent = |c: usize| {
            let (lo, hi) = contact
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &k| {
                    (l.min(self.q[6 * k + c]), h.max(self.q[6 * k + c]))
                });
            if contact.is_empty() { 0.0 } else { hi - lo }
        };
        StaticPress {
            deflection: self.deflection,
            load,
            bead_force,
            nodes_in_contact: contact.len(),
            patch_length: extent(0),
            patch_width: extent(1),
            passes,
            newton_iterations: newton,
        }
    }

    /// The deflection under the vertical load `load` (N, `> 0`): the secant method on
    /// `W(delta)` from the current solution, to `|W - load| <= rel_tol load`; the first
    /// trial deflection is `guess` (m, `> 0`) beyond the current one when nothing is
    /// loaded yet. Errors name the field.
    pub fn press_to_load(&mut self, load: f64, guess: f64, rel_tol: f64) -> Result<StaticPress> {
        positive("load", load)?;
        positive("guess", guess)?;
        positive("rel_tol", rel_tol)?;
        let mut a = self.press(self.deflection)?;
        if (a.load - load).abs() <= rel_tol * load {
            return Ok(a);
        }
        let mut b = self.press(a.deflection + guess)?;
        for _ in 0..40 {
            if (b.load - load).abs() <= rel_tol * load {
                return Ok(b);
            }
            let slope = (b.load - a.load) / (b.deflection - a.deflection);
            let step = if slope > 0.0 {
                (load - b.load) / slope
            } else {
                guess
            };
            // Never more than doubling the deflection nor going below zero.
            let next = (b.deflection + step)
                .min(2.0 * b.deflection + guess)
                .max(0.5 * b.deflection);
            a = b;
            b = self.press(next)?;
        }
        Err(FeaError::invalid(
            "load",
            load,
            "the secant iteration on the deflection did not converge in 40 solves",
        ))
    }
}

/// The bead radius of `tire` against the rim's, to `tolerance` (m): every bead node at
/// the distance `rim_radius` from the axle (the `Y` axis through the geometry's centre).
/// Errors name `rim.radius` with both radii.
pub fn check_fits_rim(tire: &TireMesh, rim_radius: f64, tolerance: f64) -> Result<()> {
    positive("rim.radius", rim_radius)?;
    positive("rim.tolerance", tolerance)?;
    let c = tire.geometry.centre;
    for &n in tire.beads.iter().flatten() {
        let x = tire.mesh.node(n)?.position - c;
        let r = Vector3::new(x.x, 0.0, x.z).norm();
        if (r - rim_radius).abs() > tolerance {
            return Err(FeaError::invalid(
                "rim.radius",
                rim_radius,
                format!(
                    "does not fit the tire: bead node {} is at radius {r} m from the axle (tolerance {tolerance} m)",
                    n.0
                ),
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::ShellMaterial;
    use crate::tire_mesh::TireGeometry;

    fn geometry(n_around: usize, n_across: usize) -> TireGeometry {
        TireGeometry {
            centre: Vector3::zeros(),
            ring_radius: 0.28,
            section_radius: 0.08,
            bead_angle: 135f64.to_radians(),
            n_around,
            n_across,
            thickness: 0.004,
        }
    }

    fn on_ground(pressure: f64) -> TireOnGround {
        let m = ShellMaterial::isotropic(1e8, 0.3, 1100.0).unwrap();
        let tire = TireMesh::new(geometry(16, 4), m).unwrap();
        let inflated = InflatedTire::new(&tire, pressure, BeadMount::Hinged, 4).unwrap();
        TireOnGround::new(&tire, &inflated, BeadMount::Hinged).unwrap()
    }

    /// The ground's load equals the force through the beads (the pressure has no
    /// resultant on the open carcass), no node is below the ground or pulls on it, the
    /// load grows with the deflection, and a target load is met by the secant iteration.
    #[test]
    fn pressed_tire_is_in_equilibrium_and_stiffens_with_pressure() {
        let mut soft = on_ground(1.0e5);
        let (a, b) = (soft.press(0.002).unwrap(), soft.press(0.004).unwrap());
        for s in [&a, &b] {
            assert!(s.load > 0.0 && s.nodes_in_contact >= 1, "{s:?}");
            assert!((s.bead_force - s.load).abs() <= 1e-7 * s.load, "{s:?}");
        }
        assert!(b.load > a.load, "{a:?} {b:?}");
        let q = soft.coordinates();
        let z_min = (0..q.len() / 6)
            .map(|k| q[6 * k + 2])
            .fold(f64::INFINITY, f64::min);
        assert!(
            z_min >= soft.z_contact - 1e-12,
            "{z_min} {}",
            soft.z_contact
        );
        let w = soft.press_to_load(500.0, 0.001, 1e-6).unwrap();
        assert!((w.load - 500.0).abs() <= 5e-4, "{w:?}");
        let mut stiff = on_ground(2.0e5);
        let v = stiff.press_to_load(500.0, 0.001, 1e-6).unwrap();
        assert!(v.deflection < w.deflection, "{v:?} {w:?}");
    }

    #[test]
    fn bad_input_names_the_field() {
        let m = ShellMaterial::isotropic(1e8, 0.3, 1100.0).unwrap();
        let tire = TireMesh::new(geometry(16, 4), m).unwrap();
        for p in [0.0, -1e5, f64::NAN] {
            let e = InflatedTire::new(&tire, p, BeadMount::Hinged, 1)
                .unwrap_err()
                .to_string();
            assert!(e.contains("pressure"), "{e}");
        }
        // The bead ring sits at R_c - a |cos phi_b| = 0.2234 m; a rim 5 mm larger does not
        // fit at a 1 mm tolerance, the right one does.
        let r = geometry(16, 4).bead_radius();
        check_fits_rim(&tire, r, 1e-6).unwrap();
        let e = check_fits_rim(&tire, r + 0.005, 1e-3)
            .unwrap_err()
            .to_string();
        assert!(e.contains("rim.radius") && e.contains("bead node"), "{e}");
        assert!(
            check_fits_rim(&tire, -0.2, 1e-3)
                .unwrap_err()
                .to_string()
                .contains("rim.radius")
        );
        let e = TireMesh::new(
            TireGeometry {
                thickness: 0.0,
                ..geometry(16, 4)
            },
            m,
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("thickness"), "{e}");
        for young in [0.0, -1e8] {
            let e = ShellMaterial::isotropic(young, 0.3, 1100.0)
                .unwrap_err()
                .to_string();
            assert!(e.contains("material.young"), "{e}");
        }
        let mut g = on_ground(1.0e5);
        assert!(
            g.press(-0.001)
                .unwrap_err()
                .to_string()
                .contains("deflection")
        );
        assert!(
            g.press_to_load(0.0, 0.001, 1e-4)
                .unwrap_err()
                .to_string()
                .contains("load")
        );
    }
}
