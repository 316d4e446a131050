//! [`SphBuilder`]: particles on a lattice (fluid blocks, wall marker layers, tanks).

use chrono_core::particles::Kernel;
use chrono_core::particles::lattice::{Fit, Lattice, ParticleSet, Tank, WallMarker};

use crate::data::{Kind, ParticleData};
use crate::eos::Tait;
use crate::error::{Result, SphError, finite3};
use crate::motion::WallMotion;
use crate::settings::SphSettings;
use crate::system::SphSystem;

/// Which faces of a tank carry wall layers: `[-x, +x, -y, +y, -z, +z]`
/// ([`chrono_core::particles::lattice::Sides`]).
pub type TankSides = chrono_core::particles::lattice::Sides;

/// Builds an [`SphSystem`]: particles are placed on the cubic lattice of spacing `dp`
/// aligned with the boxes given (centres at `lower + (i + 1/2) dp`), fluid mass
/// `m = rho dp^3` with `rho` the initial density, wall markers `m = rho_0 dp^3`.
#[derive(Debug, Clone)]
pub struct SphBuilder {
    settings: SphSettings,
    eos: Tait,
    motion: WallMotion,
    data: ParticleData,
    carriers: Vec<crate::carrier::Carrier>,
    point_carriers: Vec<crate::carrier::PointCarrier>,
}

fn check_box(field: &str, lower: [f64; 3], upper: [f64; 3]) -> Result<()> {
    finite3(&format!("{field}.lower"), lower)?;
    finite3(&format!("{field}.upper"), upper)?;
    for a in 0..3 {
        if upper[a] <= lower[a] {
            return Err(SphError::invalid(
                format!("{field}.upper[{a}]"),
                upper[a],
                format!("must exceed lower[{a}] = {}", lower[a]),
            ));
        }
    }
    Ok(())
}

impl SphBuilder {
    /// A builder with validated settings.
    pub fn new(settings: SphSettings) -> Result<Self> {
        settings.validate()?;
        let eos = Tait::new(settings.rho0, settings.gamma, settings.sound_speed)?;
        Ok(Self {
            settings,
            eos,
            motion: WallMotion::Fixed,
            data: ParticleData::default(),
            carriers: Vec::new(),
            point_carriers: Vec::new(),
        })
    }

    /// The prescribed motion of all wall markers.
    pub fn motion(mut self, motion: WallMotion) -> Result<Self> {
        motion.validate()?;
        self.motion = motion;
        Ok(self)
    }

    /// The settings.
    pub fn settings(&self) -> &SphSettings {
        &self.settings
    }

    /// Fills the box `[lower, upper]` with fluid; returns the number added. With
    /// `free_surface = Some(z_s)` the density is hydrostatic,
    /// `rho = Tait::hydrostatic_density(|g|, z_s - z)` (exact compressible balance
    /// `dp/dz = -rho |g|`, `p = 0` at `z_s`), else `rho_0`.
    pub fn add_fluid_box(
        &mut self,
        lower: [f64; 3],
        upper: [f64; 3],
        free_surface: Option<f64>,
    ) -> Result<usize> {
        check_box("fluid_box", lower, upper)?;
        let dp = self.settings.spacing;
        let points = Lattice::new(lower, dp)?.fill(lower, upper, Fit::Floor)?;
        Ok(self.add_fluid_points(&points, free_surface))
    }

    /// Adds fluid particles at `points` (m, on the lattice of spacing `dp`, e.g. from
    /// [`chrono_core::particles::lattice`]); returns the number added. Density as in
    /// [`add_fluid_box`](Self::add_fluid_box).
    pub fn add_fluid_points(&mut self, points: &[[f64; 3]], free_surface: Option<f64>) -> usize {
        let dp = self.settings.spacing;
        let g = {
            let g = self.settings.gravity;
            (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt()
        };
        let before = self.data.len();
        for &p in points {
            let rho = match free_surface {
                Some(zs) => self.eos.hydrostatic_density(g, zs - p[2]),
                None => self.settings.rho0,
            };
            self.data.push(Kind::Fluid, p, rho, rho * dp * dp * dp, 0);
        }
        self.data.len() - before
    }

    /// Fills the box `[lower, upper]` with wall markers of `group`; returns the number
    /// added. These markers carry no wall normal, so their no-slip velocity is Adami's
    /// mirrored average ([`NoSlip::Adami`](crate::NoSlip::Adami)).
    pub fn add_wall_box(&mut self, lower: [f64; 3], upper: [f64; 3], group: u16) -> Result<usize> {
        check_box("wall_box", lower, upper)?;
        let dp = self.settings.spacing;
        let points = Lattice::new(lower, dp)?.fill(lower, upper, Fit::Floor)?;
        let m = self.settings.rho0 * dp * dp * dp;
        for &p in &points {
            self.data
                .push_with_normal(Kind::Wall, p, self.settings.rho0, m, group, [0.0; 3], 0.0);
        }
        Ok(points.len())
    }

    /// Wall layers around the inner box `[inner_lower, inner_upper]` on the chosen
    /// `sides` (`layers` markers thick; `layers dp` must cover the kernel support `2 h`),
    /// lattice-aligned with the inner box. Faces of a side that is off are left open
    /// (an open top, or a periodic direction). Returns the number of markers added.
    /// Groups: `group_base + face` (0..6 in the order of [`TankSides`]) for the markers
    /// whose nearest inner face is that face, so the force on one wall can be probed.
    /// Each marker records that face's inward normal and its depth behind it, for the
    /// linear no-slip extrapolation ([`NoSlip::Linear`](crate::NoSlip::Linear)).
    pub fn add_tank(
        &mut self,
        inner_lower: [f64; 3],
        inner_upper: [f64; 3],
        layers: usize,
        sides: TankSides,
        group_base: u16,
    ) -> Result<usize> {
        check_box("tank", inner_lower, inner_upper)?;
        let dp = self.settings.spacing;
        if (layers as f64) * dp < 2.0 * self.settings.h() - 1e-9 * dp {
            return Err(SphError::invalid(
                "tank.layers",
                layers,
                format!(
                    "layers * spacing must cover the kernel support 2 h = {} m",
                    2.0 * self.settings.h()
                ),
            ));
        }
        let tank = Tank::new(inner_lower, inner_upper, layers, sides);
        // every box on its own lattice: the walls' from the outer corner
        let walls = Lattice::new(tank.outer(dp).0, dp)?.tank(&tank, Fit::Floor)?;
        Ok(self.add_wall_markers(&walls, group_base))
    }

    /// Adds the wall markers `walls` (e.g. of a [`Tank`] or a
    /// [`SlabTank`](chrono_core::particles::lattice::SlabTank)) grouped by face (face by
    /// face, `group_base + face`), each with its face's inward normal and its depth;
    /// returns the number added.
    pub fn add_wall_markers(&mut self, walls: &[WallMarker], group_base: u16) -> usize {
        let dp = self.settings.spacing;
        let m = self.settings.rho0 * dp * dp * dp;
        for face in 0..6 {
            for w in walls.iter().filter(|w| w.face == face) {
                self.data.push_with_normal(
                    Kind::Wall,
                    w.position,
                    self.settings.rho0,
                    m,
                    group_base + face as u16,
                    w.normal,
                    w.depth,
                );
            }
        }
        walls.len()
    }

    /// Adds wall markers carried by a rigid motion (a body moved from outside, see
    /// [`crate::carrier`]): `local` are the body-frame offsets (m) from the motion's centre,
    /// placed at `motion`'s pose at its `t0`; the markers are in wall group `group` (for
    /// [`SphSystem::wall_force`]). Returns the carrier index
    /// ([`SphSystem::set_carrier_motion`], [`SphSystem::take_carrier_impulse`]). The markers
    /// have no wall normal: their no-slip velocity is Adami's `2 v_m - v~_f`.
    pub fn add_rigid_markers(
        &mut self,
        motion: crate::carrier::RigidMotion,
        local: &[[f64; 3]],
        group: u16,
    ) -> Result<usize> {
        motion.validate("carrier motion")?;
        if local.is_empty() {
            return Err(SphError::invalid(
                "rigid markers",
                0,
                "add at least one marker",
            ));
        }
        for (i, p) in local.iter().enumerate() {
            finite3(&format!("rigid markers[{i}]"), *p)?;
        }
        let k = self.carriers.len();
        let dp = self.settings.spacing;
        let m = self.settings.rho0 * dp * dp * dp;
        let (c, r) = motion.pose_at(motion.t0);
        for p in local {
            let x = c + r * nalgebra::Vector3::new(p[0], p[1], p[2]);
            self.data
                .push(Kind::Wall, [x.x, x.y, x.z], self.settings.rho0, m, group);
            let last = self.data.len() - 1;
            self.data.anchor[last] = *p;
            self.data.carrier[last] = k as u32;
        }
        self.carriers.push(crate::carrier::Carrier::new(motion));
        Ok(k)
    }

    /// Adds wall markers of a point carrier (a deformable body moved from outside, see
    /// [`crate::carrier`]): `positions` (m) at time 0, at rest until
    /// [`SphSystem::set_point_motion`]; wall group `group`. Returns the point carrier's
    /// index ([`SphSystem::take_point_impulses`]). The markers have no wall normal: their
    /// no-slip velocity is Adami's `2 v_m - v~_f`.
    pub fn add_point_markers(&mut self, positions: &[[f64; 3]], group: u16) -> Result<usize> {
        if positions.is_empty() {
            return Err(SphError::invalid(
                "point markers",
                0,
                "add at least one marker",
            ));
        }
        for (i, p) in positions.iter().enumerate() {
            finite3(&format!("point markers[{i}]"), *p)?;
        }
        let k = self.point_carriers.len();
        let dp = self.settings.spacing;
        let m = self.settings.rho0 * dp * dp * dp;
        let first_id = self.data.len() as u32;
        for p in positions {
            self.data.push(Kind::Wall, *p, self.settings.rho0, m, group);
            let last = self.data.len() - 1;
            self.data.carrier[last] = crate::carrier::POINT_CARRIER | k as u32;
        }
        self.point_carriers.push(crate::carrier::PointCarrier::new(
            first_id,
            positions.to_vec(),
        ));
        Ok(k)
    }

    /// Adds a particle set: its fluid ([`add_fluid_points`](Self::add_fluid_points), with
    /// the hydrostatic density below `free_surface` if given), then its walls
    /// ([`add_wall_markers`](Self::add_wall_markers) from group 0). Returns the number
    /// added.
    pub fn add_particles(&mut self, set: &ParticleSet, free_surface: Option<f64>) -> usize {
        self.add_fluid_points(&set.fluid, free_surface) + self.add_wall_markers(&set.walls, 0)
    }

    /// Number of particles so far.
    pub fn len(&self) -> usize {
        self.data.len()
    }

    /// Whether no particle was added yet.
    pub fn is_empty(&self) -> bool {
        self.data.is_empty()
    }

    /// The system. Errors when there is no fluid particle or the grid cannot be built.
    pub fn build(self) -> Result<SphSystem> {
        if !self.data.kind.contains(&crate::data::FLUID) {
            return Err(SphError::invalid("fluid particles", 0, "add at least one"));
        }
        let kernel = Kernel::new(self.settings.kernel, self.settings.h(), 3)?;
        SphSystem::new(
            self.settings,
            kernel,
            self.eos,
            self.motion,
            self.data,
            self.carriers,
            self.point_carriers,
        )
    }
}
