//! [`SphBuilder`]: particles on a lattice (fluid blocks, wall marker layers, tanks).

use chrono_core::particles::Kernel;

use crate::data::{Kind, ParticleData};
use crate::eos::Tait;
use crate::error::{Result, SphError, finite3};
use crate::motion::WallMotion;
use crate::settings::SphSettings;
use crate::system::SphSystem;

/// Which faces of a tank carry wall layers: `[-x, +x, -y, +y, -z, +z]`.
pub type TankSides = [bool; 6];

/// Builds an [`SphSystem`]: particles are placed on the cubic lattice of spacing `dp`
/// aligned with the boxes given (centres at `lower + (i + 1/2) dp`), fluid mass
/// `m = rho dp^3` with `rho` the initial density, wall markers `m = rho_0 dp^3`.
#[derive(Debug, Clone)]
pub struct SphBuilder {
    settings: SphSettings,
    eos: Tait,
    motion: WallMotion,
    data: ParticleData,
}

/// Lattice counts along each axis for a box, with a tolerance for round-off.
fn counts(lower: [f64; 3], upper: [f64; 3], dp: f64) -> [usize; 3] {
    std::array::from_fn(|a| (((upper[a] - lower[a]) / dp) + 1e-6).floor().max(0.0) as usize)
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
        let n = counts(lower, upper, dp);
        let g = {
            let g = self.settings.gravity;
            (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt()
        };
        let before = self.data.len();
        for k in 0..n[2] {
            for j in 0..n[1] {
                for i in 0..n[0] {
                    let p = [
                        lower[0] + (i as f64 + 0.5) * dp,
                        lower[1] + (j as f64 + 0.5) * dp,
                        lower[2] + (k as f64 + 0.5) * dp,
                    ];
                    let rho = match free_surface {
                        Some(zs) => self.eos.hydrostatic_density(g, zs - p[2]),
                        None => self.settings.rho0,
                    };
                    self.data.push(Kind::Fluid, p, rho, rho * dp * dp * dp, 0);
                }
            }
        }
        Ok(self.data.len() - before)
    }

    /// Fills the box `[lower, upper]` with wall markers of `group`; returns the number
    /// added. These markers carry no wall normal, so their no-slip velocity is Adami's
    /// mirrored average ([`NoSlip::Adami`](crate::NoSlip::Adami)).
    pub fn add_wall_box(&mut self, lower: [f64; 3], upper: [f64; 3], group: u16) -> Result<usize> {
        check_box("wall_box", lower, upper)?;
        self.add_walls_where(lower, upper, group, |_| Some(([0.0; 3], 0.0)))
    }

    fn add_walls_where(
        &mut self,
        lower: [f64; 3],
        upper: [f64; 3],
        group: u16,
        keep: impl Fn([f64; 3]) -> Option<([f64; 3], f64)>,
    ) -> Result<usize> {
        let dp = self.settings.spacing;
        let n = counts(lower, upper, dp);
        let m = self.settings.rho0 * dp * dp * dp;
        let before = self.data.len();
        for k in 0..n[2] {
            for j in 0..n[1] {
                for i in 0..n[0] {
                    let p = [
                        lower[0] + (i as f64 + 0.5) * dp,
                        lower[1] + (j as f64 + 0.5) * dp,
                        lower[2] + (k as f64 + 0.5) * dp,
                    ];
                    if let Some((normal, depth)) = keep(p) {
                        self.data.push_with_normal(
                            Kind::Wall,
                            p,
                            self.settings.rho0,
                            m,
                            group,
                            normal,
                            depth,
                        );
                    }
                }
            }
        }
        Ok(self.data.len() - before)
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
        let t = layers as f64 * dp;
        let mut lo = inner_lower;
        let mut hi = inner_upper;
        for a in 0..3 {
            if sides[2 * a] {
                lo[a] -= t;
            }
            if sides[2 * a + 1] {
                hi[a] += t;
            }
        }
        let mut added = 0;
        for face in 0..6 {
            if !sides[face] {
                continue;
            }
            let (a, upper_side) = (face / 2, face % 2 == 1);
            added += self.add_walls_where(lo, hi, group_base + face as u16, |p| {
                // outside the inner box, and this face is the one of largest overshoot
                let over: [f64; 6] = std::array::from_fn(|f| {
                    let ax = f / 2;
                    if f % 2 == 0 {
                        inner_lower[ax] - p[ax]
                    } else {
                        p[ax] - inner_upper[ax]
                    }
                });
                let mine = if upper_side {
                    over[2 * a + 1]
                } else {
                    over[2 * a]
                };
                if mine <= 0.0 {
                    return None;
                }
                let nearest =
                    (0..6).all(|f| f == face || over[f] < mine || (over[f] == mine && f > face));
                // inward normal of this face, depth behind it
                let mut normal = [0.0; 3];
                normal[a] = if upper_side { -1.0 } else { 1.0 };
                nearest.then_some((normal, mine))
            })?;
        }
        Ok(added)
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
        SphSystem::new(self.settings, kernel, self.eos, self.motion, self.data)
    }
}
