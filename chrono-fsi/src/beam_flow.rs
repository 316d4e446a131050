//! A flexible beam clamped in a slow flow: one cell of a square array of ANCF beams
//! (pitch `P` in x and y) in WCSPH fluid, triply periodic, the flow driven along x by a
//! body force on the fluid. No gravity (a neutrally buoyant beam, or one whose weight is
//! carried by its clamp).
//!
//! The beam (round section of diameter `D`, length `L`, `n` elements) stands along z,
//! clamped at its root (position and slope direction held) at `z = gap / 2`; its tip is
//! `gap` below the root of its periodic image above, so the fluid sees an almost
//! continuous cylinder: away from the ends, a square array of cylinders at solid fraction
//! `c = pi D^2 / (4 P^2)` (the Stokes drag of which is the reference of
//! `fsi-flexible-beam`). In steady state the fluid's drag balances the body force on the
//! cell's fluid, `F = rho f V_fluid`.
//!
//! The box is rounded to whole spacings (`P`, `L + gap`); the fluid is carved around the
//! beam ([`FsiBuilder`]).
//!
//! ```
//! use chrono_fsi::beam_flow::{BeamFlowParams, beam_in_flow};
//!
//! let p = BeamFlowParams {
//!     diameter: 0.02,
//!     length: 0.12,
//!     elements: 3,
//!     young: 1e6,
//!     beam_density: 1000.0,
//!     pitch: 0.05,
//!     gap: 0.02,
//!     rho: 1000.0,
//!     viscosity: 1.0,
//!     body_force: 0.07,
//!     spacing: 0.005,
//!     speed_estimate: 0.01,
//! };
//! let solver = chrono_ccp::Psor::new(Default::default());
//! let mut scene = beam_in_flow(&p, Box::new(solver)).unwrap();
//! scene.system.step(4e-3).unwrap();
//! // the flow pushes the beam along x
//! assert!(scene.fluid().cable_force(0).unwrap().x > 0.0);
//! assert!(scene.tip_displacement().norm() < 1e-3);
//! ```

use std::f64::consts::PI;

use chrono_core::System;
use chrono_core::descriptor::CcpSolver;
use chrono_core::item::ItemHandle;
use chrono_core::math::Vector3;
use chrono_fea::{BeamMaterial, CableItem, CableMesh, CableQuadrature, NodeId};
use chrono_sph::SphSettings;

use crate::error::{FsiError, Result};
use crate::periodic::DrivenCell;
use crate::{FsiBuilder, SphFluid};

/// Parameters of [`beam_in_flow`] (SI units).
#[derive(Debug, Clone, PartialEq)]
pub struct BeamFlowParams {
    /// Beam diameter `D`, m.
    pub diameter: f64,
    /// Beam length `L`, m.
    pub length: f64,
    /// Number of ANCF cable elements.
    pub elements: usize,
    /// Young's modulus, Pa.
    pub young: f64,
    /// Beam density, kg/m^3.
    pub beam_density: f64,
    /// Array pitch `P` (cell size in x and y), m.
    pub pitch: f64,
    /// Clearance between the tip and the root of the image above, m.
    pub gap: f64,
    /// Fluid density, kg/m^3.
    pub rho: f64,
    /// Dynamic viscosity, Pa s.
    pub viscosity: f64,
    /// Driving body force on the fluid along x, m/s^2.
    pub body_force: f64,
    /// Particle spacing, m.
    pub spacing: f64,
    /// Expected mean speed (m/s) for the sound speed (`c_s` from
    /// [`sound_speed_for`](chrono_sph::sound_speed_for): density variation ~1 %).
    pub speed_estimate: f64,
}

/// The scene: the system with the fluid item, which owns the beam (cable 0).
pub struct BeamFlow {
    /// The multibody system (no bodies; the fluid item with the beam).
    pub system: System,
    /// The fluid item (owns the beam: [`SphFluid::cable`]).
    pub fluid: ItemHandle,
    /// The cell size actually used (x, y, z), m.
    pub cell: [f64; 3],
    /// Root of the beam, m.
    pub root: Vector3<f64>,
    /// The beam's material.
    pub material: BeamMaterial,
}

impl BeamFlow {
    /// The fluid item.
    pub fn fluid(&self) -> &SphFluid {
        self.system
            .item::<SphFluid>(self.fluid)
            .expect("the scene's fluid item")
    }

    /// The beam's tip displacement from its straight position, m.
    pub fn tip_displacement(&self) -> Vector3<f64> {
        let c = self.fluid().cable(0).expect("the scene's beam");
        let n = c.mesh().nodes().len() - 1;
        c.mesh().node(NodeId(n)).expect("tip node").displacement()
    }
}

fn positive(field: &str, v: f64) -> Result<f64> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(FsiError::invalid(field, v, "must be finite and > 0"))
    }
}

/// The straight clamped beam of `p` with its root at `root` (m): a [`CableMesh`] of
/// `p.elements` elements, node 0 clamped, round section `A = pi D^2 / 4`,
/// `I = pi D^4 / 64`, no structural damping.
pub fn clamped_beam(p: &BeamFlowParams, root: Vector3<f64>) -> Result<CableMesh> {
    let d = p.diameter;
    let mat = BeamMaterial::new(
        p.young,
        p.beam_density,
        0.25 * PI * d * d,
        PI * d.powi(4) / 64.0,
        0.0,
    )
    .map_err(|e| FsiError::invalid("beam material", "", e.to_string()))?;
    let mut mesh = CableMesh::straight(
        root,
        root + Vector3::z() * p.length,
        p.elements,
        mat,
        CableQuadrature::default(),
    )
    .map_err(|e| FsiError::invalid("beam mesh", "", e.to_string()))?;
    mesh.clamp(NodeId(0))
        .map_err(|e| FsiError::invalid("beam clamp", "", e.to_string()))?;
    Ok(mesh)
}

/// Builds the scene of `p` (see the [module docs](self)) with the multibody `solver`.
/// Errors name the parameter: a value not finite or not positive, fewer than 3 elements
/// (the drag is read on the inner ones), a gap below two kernel supports, a beam not
/// resolved by the spacing (see [`crate::cable`]), a pitch below `2 D`.
pub fn beam_in_flow(p: &BeamFlowParams, solver: Box<dyn CcpSolver>) -> Result<BeamFlow> {
    for (f, v) in [
        ("diameter", p.diameter),
        ("length", p.length),
        ("young", p.young),
        ("beam_density", p.beam_density),
        ("pitch", p.pitch),
        ("gap", p.gap),
        ("rho", p.rho),
        ("viscosity", p.viscosity),
        ("spacing", p.spacing),
        ("speed_estimate", p.speed_estimate),
    ] {
        positive(f, v)?;
    }
    if !p.body_force.is_finite() {
        return Err(FsiError::invalid(
            "body_force",
            p.body_force,
            "must be finite",
        ));
    }
    if p.elements < 3 {
        return Err(FsiError::invalid(
            "elements",
            p.elements,
            "must be >= 3 (the drag per length is read on the inner elements)",
        ));
    }
    if p.pitch < 2.0 * p.diameter {
        return Err(FsiError::invalid(
            "pitch",
            p.pitch,
            format!("must be at least 2 diameters ({} m)", 2.0 * p.diameter),
        ));
    }
    let dp = p.spacing;
    let defaults = SphSettings::default();
    let support = 2.0 * defaults.h_over_dp * dp;
    if p.gap < support {
        return Err(FsiError::invalid(
            "gap",
            p.gap,
            format!(
                "must be at least the kernel support ({support} m) so the fluid between tip and root is resolved"
            ),
        ));
    }
    let snap = |x: f64| ((x / dp).round().max(1.0)) * dp;
    let (px, lz) = (snap(p.pitch), snap(p.length + p.gap));
    let cell = [px, px, lz];
    let (settings, mut system) = DrivenCell {
        cell,
        spacing: dp,
        h_over_dp: defaults.h_over_dp,
        rho: p.rho,
        viscosity: p.viscosity,
        body_force: p.body_force,
        v_max: 2.0 * p.speed_estimate,
        diameter: p.diameter,
        shifting: None,
    }
    .build(solver)?;
    let root = Vector3::new(0.5 * px, 0.5 * px, 0.5 * (lz - p.length));
    let mesh = clamped_beam(p, root)?;
    let material = *mesh.elements()[0].material();
    let mut cable =
        CableItem::new("beam", mesh).map_err(|e| FsiError::invalid("beam", "", e.to_string()))?;
    cable.set_contact_enabled(false);
    let mut fsi = FsiBuilder::new(settings)?;
    fsi.add_fluid_box([0.0; 3], cell, None)?;
    fsi.add_cable(cable)?;
    let fluid = system.add_item(Box::new(fsi.build("fluid", 1)?));
    Ok(BeamFlow {
        system,
        fluid,
        cell,
        root,
        material,
    })
}
