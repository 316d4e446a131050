//! A rigid box floating in a quasi-2D tank of constraint fluid ([`FloatingBox`], built
//! into a [`FloatingScene`]), and the probes that read its draft against Archimedes'
//! principle ([`far_surface`], [`hydrostatic_depth`], [`volume_level`],
//! [`surface_layer_density`], [`particles_inside`]).
//!
//! The tank is a slab periodic in y, [`slab_layers`] particles thick, with marker walls
//! at x-, x+ and the floor plus fixed box colliders behind them (so a sinking body lands on
//! the floor), filled with water to `depth`. The box `box_width x slab x box_height` spans
//! the slab (its markers are periodic in y like the fluid), centred in x, its bottom
//! `initial_draft` below the still water surface (the fluid lattice is cut out where the
//! box is). It is coupled to the fluid as [`Coupling`] says. Being a slice of an infinitely
//! long body, it heaves, sways and pitches; its roll and yaw are suppressed
//! ([`PLANAR_INERTIA_FACTOR`]).
//!
//! Archimedes: a box lighter than water floats with
//! `draft = (rho_box / rho_water) box_height`.

use chrono_core::descriptor::CcpSolver;
use chrono_core::error::{ChronoError, Result};
use chrono_core::item::ItemHandle;
use chrono_core::math::{Isometry3, Vector3};
use chrono_core::particles::lattice::Fit;
use chrono_core::particles::lattice::{Lattice, SLAB_SIDES, Tank, slab_layers, wall_layers};
use chrono_core::{BodyHandle, ContactMaterial, RigidBodyBuilder, Shape, System, SystemSettings};
use serde::{Deserialize, Serialize};

use crate::fluid::ConstraintFluid;
use crate::geometry::box_markers;
use crate::settings::{CfluidSettings, SurfaceMode};

/// Factor on the box's moments of inertia about x and z (roll and yaw of a body that
/// spans the periodic slab): large enough that those rotations stay negligible, small
/// enough to keep `M^-1` well scaled.
pub const PLANAR_INERTIA_FACTOR: f64 = 1e6;

/// How the floating box is coupled to the fluid.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum Coupling {
    /// Markers in the fluid's density rows, plus the particles' contact spheres.
    #[serde(rename = "markers")]
    Markers,
    /// The same, and a density row per marker (the default model of chrono-cfluid).
    #[default]
    #[serde(rename = "marker-rows")]
    MarkerRows,
    /// Contact spheres only.
    #[serde(rename = "contact")]
    Contact,
}

/// The floating-box scene: geometry (m), densities (kg/m^3) and the fluid model.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FloatingBox {
    /// Box density, kg/m^3.
    pub box_density: f64,
    /// Box width (x), m (a whole number of spacings).
    pub box_width: f64,
    /// Box height (z), m (a whole number of spacings).
    pub box_height: f64,
    /// Initial draft (box bottom below the still water surface), m (a whole number of
    /// spacings, below `min(depth, box_height)`).
    pub initial_draft: f64,
    /// Tank length (x), m (a whole number of spacings, 4 spacings each side of the box).
    pub tank_length: f64,
    /// Still water depth, m (a whole number of spacings).
    pub depth: f64,
    /// Particle spacing, m.
    pub spacing: f64,
    /// Smoothing length over spacing `h_k / dp`.
    pub h_over_dp: f64,
    /// XSPH viscosity epsilon.
    pub xsph: f64,
    /// Fluid–box coupling.
    pub coupling: Coupling,
    /// Radius of the particles' contact spheres over the spacing, in `[0, 1]`.
    pub contact_radius: f64,
    /// Position projection sweeps per step (`CfluidSettings::position_iterations`).
    pub position_iterations: u32,
    /// Compression at which the projection stops.
    pub position_tolerance: f64,
    /// Free-surface treatment of the density rows.
    pub surface: SurfaceMode,
    /// Density rows for the tank's wall markers (`CfluidSettings::wall_marker_rows`).
    pub wall_rows: bool,
}

impl Default for FloatingBox {
    /// A 500 kg/m^3 box 0.16 m x 0.08 m in 0.16 m of water, tank 0.48 m, `dp = 0.01` m.
    fn default() -> Self {
        Self {
            box_density: 500.0,
            box_width: 0.16,
            box_height: 0.08,
            initial_draft: 0.0,
            tank_length: 0.48,
            depth: 0.16,
            spacing: 0.01,
            h_over_dp: CfluidSettings::default().h_over_dp,
            xsph: CfluidSettings::default().xsph,
            coupling: Coupling::MarkerRows,
            contact_radius: 0.5,
            position_iterations: 0,
            position_tolerance: 1e-4,
            surface: SurfaceMode::OneSided,
            wall_rows: false,
        }
    }
}

/// Whether `x` is a whole positive number of spacings `dp`.
fn whole(x: f64, dp: f64) -> bool {
    let c = x / dp;
    c.round() >= 1.0 && (c - c.round()).abs() < 1e-6 * c.max(1.0)
}

impl FloatingBox {
    /// The expected draft of a floating box, `(rho_box / rho_water) box_height`, m.
    pub fn archimedes_draft(&self) -> f64 {
        self.box_density / CfluidSettings::default().rest_density * self.box_height
    }

    /// Checks the set-up; the error names the field and its value.
    pub fn check(&self) -> Result<()> {
        let dp = self.spacing;
        if !(dp.is_finite() && dp > 0.0) {
            return Err(ChronoError::invalid("spacing", dp, "must be > 0"));
        }
        for (name, v) in [
            ("box_width", self.box_width),
            ("box_height", self.box_height),
            ("depth", self.depth),
            ("tank_length", self.tank_length),
        ] {
            if !(v.is_finite() && whole(v, dp)) {
                return Err(ChronoError::invalid(
                    name,
                    v,
                    format!("must be a positive multiple of `spacing` = {dp}"),
                ));
            }
        }
        if !(self.box_density.is_finite() && self.box_density > 0.0) {
            return Err(ChronoError::invalid(
                "box_density",
                self.box_density,
                "must be > 0",
            ));
        }
        if self.tank_length < self.box_width + 8.0 * dp {
            return Err(ChronoError::invalid(
                "tank_length",
                self.tank_length,
                "must leave 4 spacings each side of the box",
            ));
        }
        let d = self.initial_draft;
        if !(d.is_finite() && d >= 0.0 && whole(d + dp, dp) && d < self.depth.min(self.box_height))
        {
            return Err(ChronoError::invalid(
                "initial_draft",
                d,
                "must be a multiple of `spacing` in [0, min(depth, box_height))",
            ));
        }
        if !(0.0..=1.0).contains(&self.contact_radius) {
            return Err(ChronoError::invalid(
                "contact_radius",
                self.contact_radius,
                "must be in [0, 1]",
            ));
        }
        Ok(())
    }

    /// Builds the scene (checked first) with the CCP solver `solver` (for example
    /// `chrono_ccp::Apgd`).
    pub fn build(&self, solver: Box<dyn CcpSolver>) -> Result<FloatingScene> {
        self.check()?;
        let p = self;
        let dp = p.spacing;
        let h_over_dp = p.h_over_dp;
        let layers = wall_layers(h_over_dp);
        let ly = slab_layers(h_over_dp) as f64 * dp;
        let t = layers as f64 * dp;
        let (len, hb, wb) = (p.tank_length, p.box_height, p.box_width);
        let top = p.depth + 2.0 * hb;
        let settings = CfluidSettings {
            spacing: dp,
            xsph: p.xsph,
            contact_radius_over_dp: p.contact_radius,
            body_marker_rows: p.coupling == Coupling::MarkerRows,
            wall_marker_rows: p.wall_rows,
            h_over_dp,
            position_iterations: p.position_iterations,
            position_tolerance: p.position_tolerance,
            surface: p.surface,
            domain_lower: [-t, 0.0, -t],
            domain_upper: [len + t, ly, top],
            periodic: [false, true, false],
            ..CfluidSettings::default()
        };
        // the box: centred in x, bottom `initial_draft` below the surface
        let (xc, zb) = (0.5 * len, p.depth - p.initial_draft);
        let x_lo = xc - 0.5 * wb;
        // snap the box faces to the fluid lattice (cell faces)
        let x_lo = (x_lo / dp).round() * dp;
        let xc = x_lo + 0.5 * wb;
        let inside = |q: &[f64; 3]| q[0] > x_lo && q[0] < x_lo + wb && q[2] > zb;
        let lattice = Lattice::new([0.0; 3], dp)?;
        let fluid: Vec<[f64; 3]> = lattice
            .fill([0.0; 3], [len, ly, p.depth], Fit::Nearest)?
            .into_iter()
            .filter(|q| !inside(q))
            .collect();
        let tank = Tank::new([0.0; 3], [len, ly, top], layers, SLAB_SIDES);
        let walls: Vec<[f64; 3]> = lattice
            .tank(&tank, Fit::Nearest)?
            .into_iter()
            .map(|w| w.position)
            .collect();
        let mut item = ConstraintFluid::new("water", settings, &fluid, &walls)?;
        let mut sys = System::new(
            SystemSettings {
                envelope: 0.25 * dp,
                ..SystemSettings::default()
            },
            solver,
        )?;
        // fixed tank colliders behind the marker walls (floor and the two side walls)
        let material = ContactMaterial::with_friction(0.3);
        let yc = 0.5 * ly;
        let big = 4.0 * ly;
        add_tank_colliders(&mut sys, [len, ly, top], t, material)?;
        // the box spans the slab; its collider is longer in y (no y faces near the fluid)
        // The box is a slice of a body infinitely long in y (the slab is periodic): it may
        // heave, sway and pitch (rotate about y), but a roll or yaw (about x or z) would tilt
        // it through its own periodic images. Those two rotations are suppressed by giving
        // them [`PLANAR_INERTIA_FACTOR`] times the slice's moment of inertia.
        let mass = p.box_density * wb * ly * hb;
        let inertia = Vector3::new(
            PLANAR_INERTIA_FACTOR * mass * (ly * ly + hb * hb) / 12.0,
            mass * (wb * wb + hb * hb) / 12.0,
            PLANAR_INERTIA_FACTOR * mass * (wb * wb + ly * ly) / 12.0,
        );
        let body = sys.add_body(
            RigidBodyBuilder::dynamic()
                .name("box")
                .mass(mass)
                .inertia_diagonal(inertia)
                .position(Vector3::new(xc, yc, zb + 0.5 * hb))
                .collider(
                    Shape::Box {
                        half_extents: Vector3::new(0.5 * wb, big, 0.5 * hb),
                    },
                    Isometry3::identity(),
                    material,
                ),
        )?;
        if p.coupling != Coupling::Contact {
            let markers = box_markers(
                [0.5 * wb, 0.5 * ly, 0.5 * hb],
                dp,
                layers,
                [false, true, false],
            )?;
            item.attach_body(body, sys.body(body)?, &markers)?;
        }
        let id = sys.add_item(Box::new(item));
        Ok(FloatingScene { sys, id, body, ly })
    }
}

/// Fixed box colliders behind the floor and the two end walls of the slab tank
/// `[0, len] x [0, ly] x [0, top]` (`dims`, m), `t` thick (m; the marker walls' depth), four
/// times the slab's width across y (no faces near a periodic slab's fluid), of `material`:
/// the fluid's contact spheres and a body that sinks land on them, whatever the marker
/// walls' rows do.
pub fn add_tank_colliders(
    sys: &mut System,
    dims: [f64; 3],
    t: f64,
    material: ContactMaterial,
) -> Result<()> {
    let [len, ly, top] = dims;
    let (yc, big) = (0.5 * ly, 4.0 * ly);
    let wall = |c: [f64; 3], half: [f64; 3]| {
        RigidBodyBuilder::fixed().collider(
            Shape::Box {
                half_extents: Vector3::from(half),
            },
            Isometry3::translation(c[0], c[1], c[2]),
            material,
        )
    };
    sys.add_body(wall([0.5 * len, yc, -t], [0.5 * len + 2.0 * t, big, t]))?;
    sys.add_body(wall([-t, yc, 0.5 * top], [t, big, 0.5 * top + t]))?;
    sys.add_body(wall([len + t, yc, 0.5 * top], [t, big, 0.5 * top + t]))?;
    Ok(())
}

/// A built [`FloatingBox`]: the system, the fluid's item index, the box handle, the slab
/// thickness.
pub struct FloatingScene {
    /// The system (tank colliders, the box, the fluid item).
    pub sys: System,
    /// The fluid item's index.
    pub id: ItemHandle,
    /// The box.
    pub body: BodyHandle,
    /// Slab thickness, m.
    pub ly: f64,
}

impl FloatingScene {
    /// The fluid item.
    pub fn fluid(&self) -> Result<&ConstraintFluid> {
        self.sys.item::<ConstraintFluid>(self.id).ok_or_else(|| {
            ChronoError::invalid("scene.fluid", self.id, "the fluid item is missing")
        })
    }
}

/// The free surface far from the box: over the columns of fluid more than `2 dp` from
/// the box faces and from the walls, the mean of the highest particle's `z + dp / 2`, m.
pub fn far_surface(f: &ConstraintFluid, dp: f64, len: f64, box_x: [f64; 2]) -> f64 {
    let n_cols = (len / dp).round() as usize;
    let mut tops = vec![f64::NEG_INFINITY; n_cols];
    for i in 0..f.n_fluid() {
        let q = f.position(i);
        let c = (q[0] / dp).floor();
        if c >= 0.0 && (c as usize) < n_cols {
            let t = &mut tops[c as usize];
            *t = t.max(q[2]);
        }
    }
    let (mut sum, mut count) = (0.0, 0usize);
    for (c, t) in tops.iter().enumerate() {
        let x = (c as f64 + 0.5) * dp;
        let far = x > 2.0 * dp
            && x < len - 2.0 * dp
            && (x < box_x[0] - 2.0 * dp || x > box_x[1] + 2.0 * dp);
        if far && t.is_finite() {
            sum += t + 0.5 * dp;
            count += 1;
        }
    }
    if count == 0 {
        f64::NAN
    } else {
        sum / count as f64
    }
}

/// The hydrostatic depth of level `z` in the far field, m: the fluid mass per unit area
/// above `z` over `rho_0`, in the columns [`far_surface`] uses (a particle stands for the
/// slab `[z_p - dp/2, z_p + dp/2]`, counted by the fraction above `z`). In a fluid at
/// rest the pressure at `z` is `rho_0 g` times this, so `z` plus this depth is the level
/// where the hydrostatic pressure vanishes: the surface Archimedes' principle refers to,
/// independent of how the top particle layers pack.
pub fn hydrostatic_depth(f: &ConstraintFluid, dp: f64, len: f64, box_x: [f64; 2], z: f64) -> f64 {
    let ly = f.settings().domain_upper[1] - f.settings().domain_lower[1];
    let (mut frac, mut cols) = (0.0, 0usize);
    let n_cols = (len / dp).round() as usize;
    let far = |x: f64| {
        x > 2.0 * dp && x < len - 2.0 * dp && (x < box_x[0] - 2.0 * dp || x > box_x[1] + 2.0 * dp)
    };
    for c in 0..n_cols {
        if far((c as f64 + 0.5) * dp) {
            cols += 1;
        }
    }
    for i in 0..f.n_fluid() {
        let q = f.position(i);
        let c = (q[0] / dp).floor();
        if c >= 0.0 && (c as usize) < n_cols && far((c + 0.5) * dp) {
            frac += ((q[2] + 0.5 * dp - z) / dp).clamp(0.0, 1.0);
        }
    }
    let volume = f.particle_mass() / f.settings().rest_density;
    frac * volume / (cols as f64 * dp * ly)
}

/// The still-water level of the tank with the box bottom at `z_b`, m: the level of an
/// incompressible fluid of volume `volume` (the fluid's mass over `rho_0`, m^3) in the
/// tank of length `len` and slab `ly` beside a box of width `width`:
/// `len level - width (level - z_b) = volume / ly`.
pub fn volume_level(volume: f64, ly: f64, len: f64, width: f64, z_b: f64) -> f64 {
    (volume / ly - width * z_b) / (len - width)
}

/// Particles per lattice cell area `dp^2` in the top layer of the far columns of
/// [`far_surface`] (the particles within `dp / 2` below their column's highest one): 1 on
/// the lattice; more where the one-sided free surface lets the top layer pack.
pub fn surface_layer_density(f: &ConstraintFluid, dp: f64, len: f64, box_x: [f64; 2]) -> f64 {
    let ly = f.settings().domain_upper[1] - f.settings().domain_lower[1];
    let n_cols = (len / dp).round() as usize;
    let col = |q: [f64; 3]| {
        let c = (q[0] / dp).floor();
        let x = (c + 0.5) * dp;
        let far = x > 2.0 * dp
            && x < len - 2.0 * dp
            && (x < box_x[0] - 2.0 * dp || x > box_x[1] + 2.0 * dp);
        (c >= 0.0 && (c as usize) < n_cols && far).then_some(c as usize)
    };
    let mut tops = vec![f64::NEG_INFINITY; n_cols];
    for i in 0..f.n_fluid() {
        let q = f.position(i);
        if let Some(c) = col(q) {
            tops[c] = tops[c].max(q[2]);
        }
    }
    let cols = tops.iter().filter(|t| t.is_finite()).count();
    let top_layer = (0..f.n_fluid())
        .filter(|&i| {
            let q = f.position(i);
            col(q).is_some_and(|c| q[2] >= tops[c] - 0.5 * dp)
        })
        .count();
    if cols == 0 {
        f64::NAN
    } else {
        top_layer as f64 * dp / (cols as f64 * ly)
    }
}

/// Fluid particles whose centre is inside the box (its frame, half extents `half` in x, z).
pub fn particles_inside(f: &ConstraintFluid, pose: &Isometry3<f64>, half: [f64; 2]) -> usize {
    let inv = pose.inverse();
    (0..f.n_fluid())
        .filter(|&i| {
            let q = f.position(i);
            let l = inv * chrono_core::math::Point3::new(q[0], q[1], q[2]);
            l.x.abs() < half[0] && l.z.abs() < half[1]
        })
        .count()
}
