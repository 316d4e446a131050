//! Inflating a [`TireMesh`] and mounting it on a rigid rim.
//!
//! Inflation is a static solve: the carcass under its follower pressure with the bead
//! rings held where the rim will hold them (Newton with the pressure's load stiffness).
//! Mounting attaches each bead node to the rim body by three bilateral rows (positions:
//! hinged beads) and, for clamped beads, its director as well, so the rim carries the
//! tire's load and the inflation pressure's bead forces.

use chrono_core::BodyHandle;
use nalgebra::{Isometry3, Point3, Vector3};

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
        self.placed(&Isometry3::translation(0.0, 0.0, lift))
    }

    /// The pressurized mesh at the inflated shape moved rigidly by `pose` (positions
    /// `R r + x`, directors `R d`; the stress-free reference stays where it was: the shell's
    /// strains do not change under a rigid motion).
    pub fn placed(&self, pose: &Isometry3<f64>) -> Result<ShellMesh> {
        let mut q = self.inflated.coordinates();
        for node in q.chunks_exact_mut(6) {
            let r = pose.transform_point(&Point3::new(node[0], node[1], node[2]));
            let d = pose.transform_vector(&Vector3::new(node[3], node[4], node[5]));
            node[..3].copy_from_slice(r.coords.as_slice());
            node[3..].copy_from_slice(d.as_slice());
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
    mount_on_rim_at(
        item,
        beads,
        rim,
        &Isometry3::translation(rim_at.x, rim_at.y, rim_at.z),
        mount,
    )
}

/// [`mount_on_rim`] for a rim body whose frame (centre of mass and axes) is at `rim_pose`
/// (world): each bead node's position, and for clamped beads its director, taken into the
/// rim's frame.
pub fn mount_on_rim_at(
    item: &mut ShellItem,
    beads: &[Vec<NodeId>],
    rim: BodyHandle,
    rim_pose: &Isometry3<f64>,
    mount: BeadMount,
) -> Result<()> {
    for ring in beads {
        for &n in ring {
            let node = *item.mesh().node(n)?;
            item.attach(
                n,
                AttachTarget::Body {
                    body: rim,
                    local: rim_pose
                        .inverse_transform_point(&Point3::from(node.position))
                        .coords,
                },
            )?;
            if mount == BeadMount::Clamped {
                item.attach_director(
                    n,
                    DirectorTarget::Body {
                        body: rim,
                        local: rim_pose.inverse_transform_vector(&node.slope),
                    },
                )?;
            }
        }
    }
    Ok(())
}
