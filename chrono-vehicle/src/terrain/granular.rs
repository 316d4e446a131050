//! Granular terrain as a moving patch: a bed of spherical grains (chrono-core granular
//! bodies, NSC or SMC contact) in a box under the vehicle, of which only the part near the
//! wheels exists. As the vehicle advances, the slab of grains at the rear is moved to the
//! front, so the number of grains stays fixed however far the vehicle drives: the scene
//! models only what it needs.
//!
//! The front slab of the freshly settled bed is kept as a *template*: each relocation puts
//! the rearmost grains at the template's positions shifted to the new front, so the ground
//! ahead is always an undisturbed settled bed (not the rutted slab the wheels left behind).
//! The box's floor and side walls are planes along X, so moving the container forward by
//! the slab length changes only its front and rear walls.
//!
//! With `lanes`, the bed is one strip of `width` under each wheel track, each between its
//! own side walls, and nothing between them: for small grains this is a fraction of the
//! full-width bed (the HMMWV's 0.5 m lanes are 38 % of its 2.6 m patch).
//!
//! ```
//! use chrono_core::{System, SystemSettings};
//! use chrono_vehicle::terrain::{GranularPatch, GranularPatchParams};
//!
//! let params = GranularPatchParams {
//!     length: 2.0, width: 0.5, depth: 0.1, grain_radius: 0.02, density: 2500.0,
//!     friction: 0.8, young_modulus: 2e7, restitution: 0.3, rolling_friction: 0.2,
//!     compliance: 0.0, slab: 0.2, seed: 7,
//!     lanes: vec![-0.91, 0.91], // under the HMMWV's wheels
//! };
//! let solver = chrono_ccp::Apgd::new(chrono_ccp::SolverSettings::default());
//! let mut sys = System::new(SystemSettings::default(), Box::new(solver))?;
//! let patch = GranularPatch::build(&mut sys, &params, -1.0)?;
//! // Step the system to settle the bed, then `patch.capture_settled(&sys)?` and, as the
//! // vehicle drives, `patch.advance(&mut sys, x)?`.
//! println!("{} grains in two lanes", patch.grains().len());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use chrono_core::granular::{LatticeFill, Region, add_box_container, add_grains};
use chrono_core::math::{Isometry3, UnitQuaternion, Vector3};
use chrono_core::{BodyHandle, ContactMaterial, RigidBodyBuilder, Shape, System};
use serde::{Deserialize, Serialize};

use crate::error::{Result, VehicleError, check_positive};

/// A granular patch's description.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GranularPatchParams {
    /// Length along X (the direction of travel), m.
    pub length: f64,
    /// Width along Y, m.
    pub width: f64,
    /// Bed depth before settling, m.
    pub depth: f64,
    /// Grain radius, m (monodisperse, so a relocated grain fits any template site).
    pub grain_radius: f64,
    /// Grain density, kg/m^3.
    pub density: f64,
    /// Grain–grain and grain–wall friction coefficient.
    pub friction: f64,
    /// Young's modulus of the grains, Pa (SMC Hertz contact; NSC ignores it). The default
    /// is the project's `ContactMaterial` default, 2e7 Pa (`hmmwv-granular`'s grains).
    #[serde(default = "default_young_modulus")]
    pub young_modulus: f64,
    /// Coefficient of restitution (SMC damping; NSC contact is plastic).
    #[serde(default = "default_restitution")]
    pub restitution: f64,
    /// Rolling friction coefficient of the grains (dimensionless; see
    /// `ContactMaterial::rolling_friction`). Spheres without it roll like ball bearings
    /// under a driven wheel; real sand grains interlock, and a rolling resistance of order
    /// 0.1 is the usual stand-in for their angularity (Ai et al., Powder Technol. 206, 2011).
    #[serde(default)]
    pub rolling_friction: f64,
    /// Normal compliance of the grain contacts, m/N (NSC only; 0 = rigid). A small
    /// compliance `c` makes each contact a stiff implicit spring of stiffness `1/c` (the
    /// overlap under a load `F` is `c F`) and adds `c / h^2` to the diagonal of the
    /// contact operator, which bounds its condition number when a heavy body (a loaded
    /// wheel) rests on light grains: the case where a first-order CCP solver converges
    /// slowest (see `ContactMaterial::compliance`).
    #[serde(default)]
    pub compliance: f64,
    /// Length of the slab moved from the rear to the front at each relocation, m.
    pub slab: f64,
    /// Seed of the lattice jitter.
    pub seed: u64,
    /// Lanes: the Y of each lane's centre line, m. Empty (the default): one bed of
    /// `width` centred on `y = 0`. Otherwise one bed of `width` per lane, each between its
    /// own side walls, and nothing between the lanes: strips under the wheel tracks, so a
    /// bed of small grains costs only the ground the tires can reach.
    #[serde(default)]
    pub lanes: Vec<f64>,
}

fn default_restitution() -> f64 {
    0.3
}

fn default_young_modulus() -> f64 {
    ContactMaterial::default().young_modulus
}

impl GranularPatchParams {
    /// Check every field (the error names it).
    pub fn validate(&self) -> Result<()> {
        check_positive("granular_patch.length", self.length)?;
        check_positive("granular_patch.width", self.width)?;
        check_positive("granular_patch.depth", self.depth)?;
        check_positive("granular_patch.grain_radius", self.grain_radius)?;
        check_positive("granular_patch.density", self.density)?;
        crate::error::check_non_negative("granular_patch.friction", self.friction)?;
        check_positive("granular_patch.young_modulus", self.young_modulus)?;
        crate::error::check_non_negative("granular_patch.compliance", self.compliance)?;
        crate::error::check_non_negative("granular_patch.rolling_friction", self.rolling_friction)?;
        if !(0.0..=1.0).contains(&self.restitution) {
            return Err(VehicleError::invalid(
                "granular_patch.restitution",
                self.restitution,
                "must be in [0, 1]",
            ));
        }
        check_positive("granular_patch.slab", self.slab)?;
        if self.slab < 4.0 * self.grain_radius || self.slab > 0.25 * self.length {
            return Err(VehicleError::invalid(
                "granular_patch.slab",
                self.slab,
                format!(
                    "must hold at least two grain layers (>= 4 r = {}) and be at most a quarter of the length ({})",
                    4.0 * self.grain_radius,
                    0.25 * self.length
                ),
            ));
        }
        let mut sorted = self.lanes.clone();
        sorted.sort_by(f64::total_cmp);
        for (k, &c) in self.lanes.iter().enumerate() {
            if !c.is_finite() {
                return Err(VehicleError::invalid(
                    format!("granular_patch.lanes[{k}]"),
                    c,
                    "must be finite",
                ));
            }
        }
        for pair in sorted.windows(2) {
            // Two side walls between neighbouring lanes.
            let needed = self.width + 2.0 * self.lane_wall_thickness();
            if pair[1] - pair[0] < needed {
                return Err(VehicleError::invalid(
                    "granular_patch.lanes",
                    format!("{:?}", self.lanes),
                    format!(
                        "lanes {} and {} m overlap: centres must be at least width plus two walls ({needed} m) apart",
                        pair[0], pair[1]
                    ),
                ));
            }
        }
        if self.depth < 4.0 * self.grain_radius {
            return Err(VehicleError::invalid(
                "granular_patch.depth",
                self.depth,
                "must hold at least two grain layers",
            ));
        }
        Ok(())
    }
}

impl GranularPatchParams {
    /// Thickness of a lane's side walls, m: four grain radii, at least 2 cm (thick against
    /// a grain's travel in one step, so no grain passes through).
    pub fn lane_wall_thickness(&self) -> f64 {
        (4.0 * self.grain_radius).max(0.02)
    }

    /// The lanes' `(low y, high y)` spans, m: the one bed `[-width/2, width/2]` without
    /// lanes.
    pub fn lane_spans(&self) -> Vec<(f64, f64)> {
        if self.lanes.is_empty() {
            vec![(-0.5 * self.width, 0.5 * self.width)]
        } else {
            (self.lanes.iter())
                .map(|&c| (c - 0.5 * self.width, c + 0.5 * self.width))
                .collect()
        }
    }

    /// Check that a vehicle whose front tires reach `front_reach` m ahead of its
    /// reference point ([`front_reach`](crate::scene::front_reach)), set down with its
    /// reference in the middle of the patch, stays clear of the front wall until the first
    /// relocation (at `x = slab`): `length / 2 - slab > front_reach`. The error names
    /// `granular_patch.length`.
    pub fn check_room_for(&self, front_reach: f64) -> Result<()> {
        if 0.5 * self.length - self.slab > front_reach {
            Ok(())
        } else {
            Err(VehicleError::invalid(
                "granular_patch.length",
                self.length,
                format!(
                    "too short: the vehicle's front ({front_reach:.2} m ahead of the point the patch follows) would hit the front wall before the patch moves (needs length / 2 - slab > {front_reach:.2})"
                ),
            ))
        }
    }
}

/// A granular patch in a system (see the module documentation of `terrain::granular`).
#[derive(Debug, Clone, PartialEq)]
pub struct GranularPatch {
    params: GranularPatchParams,
    container: BodyHandle,
    grains: Vec<BodyHandle>,
    /// X of the container's rear wall, m.
    rear: f64,
    /// Settled grain centres of the front slab, relative to the front wall.
    template: Vec<Vector3<f64>>,
    /// Bed surface height after settling, m.
    surface: f64,
    relocations: usize,
    /// Scratch: grain indices sorted by x.
    order: Vec<usize>,
}

impl GranularPatch {
    /// Fill a box `[rear, rear + length] x [-width/2, width/2]` on the floor `z = 0` (or one
    /// such box of `width` around each of `lanes`) with a jittered lattice of grains (they
    /// fall and settle when the system steps).
    pub fn build(sys: &mut System, params: &GranularPatchParams, rear: f64) -> Result<Self> {
        params.validate()?;
        let p = params;
        let material = ContactMaterial {
            restitution: p.restitution,
            compliance: p.compliance,
            rolling_friction: p.rolling_friction,
            young_modulus: p.young_modulus,
            ..ContactMaterial::with_friction(p.friction)
        };
        let spans = p.lane_spans();
        let mut sites = Vec::new();
        for (k, &(y0, y1)) in spans.iter().enumerate() {
            let fill = LatticeFill {
                region: Region::Box {
                    lower: Vector3::new(rear, y0, 0.0),
                    upper: Vector3::new(rear + p.length, y1, p.depth),
                },
                r_min: p.grain_radius,
                r_max: p.grain_radius,
                gap: 0.05 * p.grain_radius,
                jitter: 0.5,
                max_count: usize::MAX,
                seed: p.seed.wrapping_add(k as u64),
            };
            sites.extend(fill.generate()?);
        }
        let container = if p.lanes.is_empty() {
            // The walls are taller than the bed so grains thrown up by the wheels stay in.
            let lower = Vector3::new(rear, -0.5 * p.width, 0.0);
            let top = Vector3::new(rear + p.length, 0.5 * p.width, 10.0 * p.depth + 1.0);
            add_box_container(sys, "granular patch", lower, top, material)?
        } else {
            add_lane_container(sys, p, rear, &spans, material)?
        };
        let grains = add_grains(sys, &sites, p.density, material)?;
        let n = grains.len();
        Ok(Self {
            params: p.clone(),
            container,
            grains,
            rear,
            template: Vec::new(),
            surface: p.depth,
            relocations: 0,
            order: (0..n).collect(),
        })
    }

    /// After the bed has settled: record the front slab as the relocation template and the
    /// bed's surface height (the mean top of the grains in the middle half of the patch).
    pub fn capture_settled(&mut self, sys: &System) -> Result<()> {
        let front = self.front();
        let slab = self.params.slab;
        self.template.clear();
        let mut tops = Vec::new();
        for &g in &self.grains {
            let c = sys.body(g)?.position();
            // A grain radius clear of the slab's rear edge: shifted to the new front, no
            // template grain overlaps the grains that stood at the old front wall.
            if c.x > front - slab + self.params.grain_radius {
                self.template.push(Vector3::new(c.x - front, c.y, c.z));
            }
            let mid = self.rear + 0.5 * self.params.length;
            if (c.x - mid).abs() < 0.25 * self.params.length {
                tops.push(c.z + self.params.grain_radius);
            }
        }
        if self.template.is_empty() || tops.is_empty() {
            return Err(VehicleError::invalid(
                "granular_patch",
                self.grains.len(),
                "no grains in the front slab or the middle of the patch after settling",
            ));
        }
        // The surface: the mean of the highest tenth of the tops (the top layer).
        tops.sort_by(|a, b| b.total_cmp(a));
        let k = (tops.len() / 10).max(1);
        self.surface = tops[..k].iter().sum::<f64>() / k as f64;
        Ok(())
    }

    /// Move the patch forward while `x` (the vehicle's position) is past its middle: each
    /// time, the `template.len()` rearmost grains go to the template sites beyond the
    /// front, at rest, and the container moves by one slab. Returns the number of
    /// relocations done now.
    pub fn advance(&mut self, sys: &mut System, x: f64) -> Result<usize> {
        if self.template.is_empty() {
            return Err(VehicleError::invalid(
                "granular_patch.template",
                0,
                "call capture_settled after the bed has settled",
            ));
        }
        let mut done = 0;
        while x > self.rear + 0.5 * self.params.length + self.params.slab {
            let positions: Vec<f64> = self
                .grains
                .iter()
                .map(|&g| sys.body(g).map(|b| b.position().x))
                .collect::<std::result::Result<_, _>>()?;
            self.order
                .sort_by(|&a, &b| positions[a].total_cmp(&positions[b]));
            let new_front = self.front() + self.params.slab;
            let new_rear = self.rear + self.params.slab;
            // Every grain that would end up behind the new rear wall moves, at least the
            // template's count; sites beyond the template's are stacked above it.
            let behind = positions
                .iter()
                .filter(|&&px| px < new_rear + self.params.grain_radius)
                .count();
            let count = behind.max(self.template.len()).min(self.grains.len());
            let (zmin, zmax) = self
                .template
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), t| {
                    (a.min(t.z), b.max(t.z))
                });
            let layer = zmax - zmin + 2.0 * self.params.grain_radius;
            let k_t = self.template.len();
            for k in 0..count {
                let gi = self.order[k];
                let site = self.template[k % k_t];
                let lift = (k / k_t) as f64 * layer;
                let b = sys.body_mut(self.grains[gi])?;
                b.set_pose(
                    Vector3::new(new_front + site.x, site.y, site.z + lift),
                    UnitQuaternion::identity(),
                )?;
                b.set_linear_velocity(Vector3::zeros())?;
                b.set_angular_velocity(Vector3::zeros())?;
            }
            self.rear += self.params.slab;
            let c = sys.body_mut(self.container)?;
            let shifted = c.position() + Vector3::new(self.params.slab, 0.0, 0.0);
            c.set_pose(shifted, c.rotation())?;
            self.relocations += 1;
            done += 1;
        }
        Ok(done)
    }

    /// X of the front wall, m.
    pub fn front(&self) -> f64 {
        self.rear + self.params.length
    }

    /// X of the rear wall, m.
    pub fn rear(&self) -> f64 {
        self.rear
    }

    /// The grains (a fixed number).
    pub fn grains(&self) -> &[BodyHandle] {
        &self.grains
    }

    /// The bed's surface height after settling, m.
    pub fn surface(&self) -> f64 {
        self.surface
    }

    /// Relocations so far.
    pub fn relocations(&self) -> usize {
        self.relocations
    }

    /// The description.
    pub fn params(&self) -> &GranularPatchParams {
        &self.params
    }
}

/// The lanes' container: one fixed body with the floor `z = 0` and the rear and front walls
/// as half-spaces (they span every lane) and two box walls beside each lane, as tall as
/// the box container's (grains thrown up by the wheels stay in their lane).
fn add_lane_container(
    sys: &mut System,
    p: &GranularPatchParams,
    rear: f64,
    spans: &[(f64, f64)],
    material: ContactMaterial,
) -> Result<BodyHandle> {
    let mut b = RigidBodyBuilder::fixed().name("granular patch");
    for (normal, at) in [
        (Vector3::z(), Vector3::new(rear, 0.0, 0.0)),
        (Vector3::x(), Vector3::new(rear, 0.0, 0.0)),
        (-Vector3::x(), Vector3::new(rear + p.length, 0.0, 0.0)),
    ] {
        b = b.collider(
            Shape::HalfSpace { normal },
            Isometry3::translation(at.x, at.y, at.z),
            material,
        );
    }
    let t = p.lane_wall_thickness();
    let height = 10.0 * p.depth + 1.0;
    // The walls reach a thickness past the front and rear walls, so no grain slips
    // between a side wall's end and a half-space.
    let half = Vector3::new(0.5 * p.length + t, 0.5 * t, 0.5 * height);
    for &(y0, y1) in spans {
        for y in [y0 - 0.5 * t, y1 + 0.5 * t] {
            b = b.collider(
                Shape::Box { half_extents: half },
                Isometry3::translation(rear + 0.5 * p.length, y, 0.5 * height),
                material,
            );
        }
    }
    Ok(sys.add_body(b)?)
}
