//! Inflating a [`TireMesh`] and mounting it on a rigid rim.
//!
//! Inflation is a static solve: the carcass under its follower pressure with the bead
//! rings held where the rim will hold them (Newton with the pressure's load stiffness).
//! Mounting attaches each bead node to the rim body by three bilateral rows (positions:
//! hinged beads) and, for clamped beads, its director as well, so the rim carries the
//! tire's load and the inflation pressure's bead forces.

use chrono_core::BodyHandle;
use nalgebra::Vector3;

use crate::AttachTarget;
use crate::error::{Result, positive};
use crate::node::NodeId;
use crate::shell_dynamics::{DirectorTarget, ShellItem};
use crate::shell_mesh::ShellMesh;
use crate::statics::{StaticReport, StaticSettings, solve_static};
use crate::tire_mesh::{TireGeometry, TireMesh};

/// How the bead rings hold to the rim.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum BeadMount {
    /// Positions only (three rows per node): the carcass hinges about the bead.
    #[default]
    Hinged,
    /// Positions and directors: the carcass is clamped in the rim.
    Clamped,
}

/// A tire inflated with its beads held: the pressurized mesh in its reference
/// configuration and its inflated coordinates.
#[derive(Debug, Clone)]
pub struct InflatedTire {
    /// The carcass with its pressure set, still in the undeformed configuration (the
    /// stress-free reference of the stepped item).
    pub mesh: ShellMesh,
    /// The inflated carcass (the static solution, beads held).
    pub inflated: ShellMesh,
    /// Newton's iterations of the inflation.
    pub report: StaticReport,
}

impl InflatedTire {
    /// Inflate `tire` to the gauge pressure `pressure` (Pa, `> 0`) with its beads held as
    /// `mount` holds them, in `load_steps` load steps. Errors name the field.
    pub fn new(
        tire: &TireMesh,
        pressure: f64,
        mount: BeadMount,
        load_steps: usize,
    ) -> Result<Self> {
        positive("pressure", pressure)?;
        let mut mesh = tire.mesh.clone();
        mesh.set_pressure(pressure)?;
        let mut inflated = mesh.clone();
        for ring in &tire.beads {
            for &n in ring {
                match mount {
                    BeadMount::Clamped => inflated.fix_node(n)?,
                    BeadMount::Hinged => inflated.fix_position(n)?,
                }
            }
        }
        let report = solve_static(
            &mut inflated,
            &StaticSettings {
                load_steps,
                ..StaticSettings::default()
            },
        )?;
        Ok(Self {
            mesh,
            inflated,
            report,
        })
    }

    /// The lowest point of the inflated mid surface (smallest node `z`), m.
    pub fn lowest_z(&self) -> f64 {
        self.inflated
            .nodes()
            .iter()
            .map(|n| n.position.z)
            .fold(f64::INFINITY, f64::min)
    }

    /// The pressurized mesh at the inflated shape raised by `lift` m along `Z`: ready for
    /// a [`ShellItem`] (reference configuration undeformed, current one inflated).
    pub fn lifted(&self, lift: f64) -> Result<ShellMesh> {
        let mut q = self.inflated.coordinates();
        for k in 0..self.mesh.nodes().len() {
            q[6 * k + 2] += lift;
        }
        let mut mesh = self.mesh.clone();
        mesh.set_coordinates(&q)?;
        Ok(mesh)
    }
}

impl TireGeometry {
    /// Radius of the bead rings about the axle, `R_c - a |cos phi_b|`, m: where a rim
    /// holds the tire.
    pub fn bead_radius(&self) -> f64 {
        self.ring_radius - self.section_radius * self.bead_angle.cos().abs()
    }
}

/// Attach the bead rings `beads` of the tire in `item` to the rim body `rim`, whose centre
/// is at `rim_at` (world, m) and which starts unrotated (its frame along the world axes),
/// as `mount` says.
pub fn mount_on_rim(
    item: &mut ShellItem,
    beads: &[Vec<NodeId>],
    rim: BodyHandle,
    rim_at: Vector3<f64>,
    mount: BeadMount,
) -> Result<()> {
    for ring in beads {
        for &n in ring {
            let node = *item.mesh().node(n)?;
            item.attach(
                n,
                AttachTarget::Body {
                    body: rim,
                    local: node.position - rim_at,
                },
            )?;
            if mount == BeadMount::Clamped {
                item.attach_director(
                    n,
                    DirectorTarget::Body {
                        body: rim,
                        local: node.slope,
                    },
                )?;
            }
        }
    }
    Ok(())
}
