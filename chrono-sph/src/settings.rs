//! Solver settings: resolution, fluid properties, boundary handling, time step criteria.

use chrono_core::math::GRAVITY;
use chrono_core::particles::KernelKind;
use serde::{Deserialize, Serialize};

use crate::error::{Result, SphError, finite3, non_negative, positive};

/// What to do when the Mach number `|v|_max / c_s` exceeds [`SphSettings::mach_limit`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum MachPolicy {
    /// Log a warning (once) and count the steps in
    /// [`SphStats::mach_warnings`](crate::SphStats::mach_warnings).
    #[default]
    Warn,
    /// Stop with [`SphError::MachExceeded`].
    Error,
}

/// The density diffusion term added to the continuity equation ("delta-SPH"), which
/// removes the high-frequency density (pressure) noise that the plain continuity
/// equation accumulates (Molteni and Colagrossi, Comput. Phys. Commun. 180 (2009)
/// 861-872), with `V_b = m_b / rho_b`, `F_ab = (dW/dr)/r` and fluid neighbours `b` only:
///
/// ```text
/// D_a = 2 delta h c_s sum_b V_b psi_ba (-F_ab)                 (kg/m^3/s)
/// ```
///
/// `D_a` is a discrete Laplacian of `psi` times `delta h c_s` (`-2 V_b F_ab` is the usual
/// SPH Laplacian weight `2 (x_ab . grad_a W_ab) / r_ab^2` with the sign flipped); the
/// pair term is antisymmetric, so it moves density between neighbours without creating
/// any, and an explicit step is stable for `delta <~ 1` at the acoustic CFL.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum DensityDiffusion {
    /// No diffusion (plain continuity equation).
    None,
    /// `psi_ba = rho_b - rho_a` (Molteni and Colagrossi 2009). Under gravity it diffuses
    /// the hydrostatic density gradient itself: still water gets a spurious flux towards
    /// the free surface and walls, which drives slow currents.
    MolteniColagrossi,
    /// Diffuses only the dynamic part of the density, `rho - rho_hydrostatic`, so a fluid at
    /// hydrostatic rest gets no flux (Fourtakas, Dominguez, Vacondio and Rogers, Comput.
    /// Fluids 190 (2019) 346-361), written with pressures:
    /// `psi_ba = ((p_b - p_a) + rho_ab g . x_ab) / c_s^2`, `x_ab = x_a - x_b`,
    /// `rho_ab = (rho_a + rho_b) / 2`. The hydrostatic pressure difference
    /// `-rho_ab g . x_ab` (trapezoidal rule of `dp = rho g . dx`) is subtracted from the
    /// pair pressure difference, and the Tait law linearized at `rho_0`
    /// (`d p / d rho = c_s^2`) turns the rest into a density difference. To first order
    /// in `p / (rho_0 c_s^2)` this is Fourtakas et al.'s `rho_ba - rho_ba^H`, with
    /// `rho_ba^H = rho_0 ((1 + rho_0 g z_ab / B)^(1/gamma) - 1)`; it costs no power
    /// function per pair, and it uses the local `rho_ab` instead of `rho_0`, so it
    /// vanishes (to the trapezoidal error, `~1e-6` of the hydrostatic density step) on
    /// the compressible rest state `dp/dz = -rho g` itself, which
    /// [`SphBuilder::add_fluid_box`](crate::SphBuilder::add_fluid_box) starts from (with
    /// `rho_0` the residual flux would be `(rho - rho_0) / rho_0 ~ 0.5 %` of the plain
    /// form's and would pump density towards the walls and the surface in still water).
    /// Without gravity it is plain density diffusion.
    #[default]
    Fourtakas,
}

/// How wall markers get the velocity the viscous term sees (no-slip condition).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum NoSlip {
    /// `v_w = 2 v_wall - v~_f`, `v~_f = sum_f v_f W_wf / sum_f W_wf` (Adami, Hu and Adams,
    /// J. Comput. Phys. 231 (2012) 7057-7075, eq. 22-23): the mirror of the kernel-averaged
    /// fluid velocity, at every marker depth alike. Deeper marker layers get too small a
    /// velocity (they mirror fluid near the wall, not fluid as far from the wall as they
    /// are), so the wall drags too little: the effective no-slip plane lies outside the
    /// wall surface (measured: steady Poiseuille flow 3.4 % too fast at `dp = L/30`).
    Adami,
    /// Linear extrapolation through the wall surface along the marker's wall normal,
    /// `v_w = v_wall - (d_w / d~_f) (v~_f - v_wall)` with `d_w` the marker's depth behind the
    /// wall surface and `d~_f = sum_f d_f W_wf / sum_f W_wf` the kernel-averaged distance of
    /// its fluid neighbours from it (`d~_f >= 0.2 h`), the kernel-averaged form of Morris,
    /// Fox and Zhu's mirrored velocities (J. Comput. Phys. 136 (1997) 214-226, sec. 3.3:
    /// `v_B = -(d_B / d_A) v_A`). Exact for a linear velocity near the wall, so the
    /// no-slip plane is the wall surface. Markers without a wall normal (from
    /// [`SphBuilder::add_wall_box`](crate::SphBuilder::add_wall_box)) use [`NoSlip::Adami`].
    #[default]
    Linear,
}

/// The active domain of an [`SphSystem`](crate::SphSystem) ("model only what the scene
/// needs"): only the fluid near the moving bodies is stepped, the rest is frozen but still
/// seen as neighbours (the rules: [`crate::system::active`]).
///
/// A *source* is a marker carrier that moves (every rigid and point carrier unless
/// [`SphSystem::set_carrier_source`](crate::SphSystem::set_carrier_source) says it
/// does not), bounded by a sphere (centre `c`, radius `r_b`). A fluid particle at `x` is
/// active while `d(x) = min over sources (|x - c| - r_b) <= radius`, re-evaluated at
/// every fluid step with the sources' current poses.
///
/// Choosing `radius`: at least the kernel support `2 h` (the fluid touching the markers
/// must move), plus the distance a body travels between two updates (one fluid step,
/// `|v| dt < 0.2 h` at the CFL limit: the step updates the set), plus the reach of the
/// disturbance that matters to the quantity measured — a length of the flow, so give it in
/// the body's size ([`from_radius`](Self::from_radius)), not in kernel supports, which
/// shrink with the spacing. A frozen region acts as a wall holding its state: it reflects
/// what reaches it. Under a free surface the disturbance that matters is the surface's
/// long-wave response (speed `sqrt(g depth)`), so the radius must grow with the time the
/// result is read: measured on a cylinder of diameter `D` towed at depth Froude number
/// 0.19 (`xtask validate fsi-active-domain`, docs/validation-fsi.md, 2026-12-07), the mean
/// drag stays within 2 % of the full run's for about `t <= 2 (r_b + radius - 2 D) /
/// sqrt(g depth)` (`r_b` the body's bounding radius): `radius` 3.6 D is +4.4 % off at
/// 0.5 s and +13 % at 0.8 s, 6 D +0.9 % at 0.8 s and +5.7 % at 1.2 s, 8 D +0.3 % at 1.2 s.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ActiveDomain {
    /// Activation distance from the sources' bounding spheres, m (`>= 2 h`).
    pub radius: f64,
    /// Neighbour-list margin, m (`>= 0`): list rows are built for the particles within
    /// `radius + margin` of a source (and wall markers within another list radius), so
    /// the list is rebuilt only when a source moved `margin` since the last build or an
    /// active particle has no row. Larger: fewer rebuilds, longer rebuilds.
    pub margin: f64,
}

/// Particle shifting after each step ([`crate::shifting`]): a Fickian diffusion of the
/// positions down the gradient of the particle concentration, `dr = -D grad C`. For fluid
/// without a free surface (periodic cells, closed ducts): it keeps the particle order that
/// a long shear flow destroys.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Shifting {
    /// The coefficient `A` (dimensionless, > 0): 2 for [`ShiftForm::LocalSpeed`] (Skillen
    /// et al. 2013), 4 for [`ShiftForm::DeltaPlus`] (Sun et al. 2017).
    pub coefficient: f64,
    /// Which velocity scales the diffusion, and the anti-clumping term.
    #[serde(default)]
    pub form: ShiftForm,
}

/// The form of a [`Shifting`] step of length `dt` (`h` the smoothing length).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ShiftForm {
    /// `D = A h |v_a| dt`, each particle by its own speed (Lind et al. 2012, J. Comput.
    /// Phys. 231:1499, in the step-size form of Skillen et al. 2013, Comput. Methods Appl.
    /// Mech. Engrg. 265:163; `A` = 2 there). Where the flow is slow (creeping flow,
    /// stagnation regions) it shifts little, while the shear still disorders the particles.
    #[default]
    LocalSpeed,
    /// `D = A h U_max dt` with `U_max` the fluid's largest speed at the step, and the
    /// concentration gradient weighted against clumping, `sum_b V_b (1 + R (W_ab /
    /// W(dp))^n) grad W_ab` with `R = 0.2`, `n = 4`: the particle shifting of the
    /// delta-plus-SPH scheme (Sun, Colagrossi, Marrone and Zhang 2017, Comput. Methods Appl.
    /// Mech. Engrg. 315:25-49), whose shift per step `CFL Ma (2h)^2 grad C` is this with
    /// `A = 4` at their step `dt = CFL h / c_0` (`Ma = U_max / c_0`).
    DeltaPlus,
}

impl Shifting {
    /// Sun et al.'s (2017) delta-plus-SPH shifting: [`ShiftForm::DeltaPlus`], `A = 4`.
    pub fn delta_plus() -> Self {
        Self {
            coefficient: 4.0,
            form: ShiftForm::DeltaPlus,
        }
    }
}

impl Default for Shifting {
    fn default() -> Self {
        Self {
            coefficient: 2.0,
            form: ShiftForm::LocalSpeed,
        }
    }
}

/// A tank wall that moves along itself ("moving belt"): the markers of wall group `group`
/// keep their positions but carry the velocity `velocity` (m/s, added to the tank's
/// [`WallMotion`](crate::WallMotion) velocity) in the continuity equation and in the
/// no-slip extrapolation, `v_w = v_wall - (d_w / d~_f) (v~_f - v_wall)`
/// ([`NoSlip::Linear`]). A plane wall translating along a periodic direction of its own
/// plane is invariant under the translation, so a wall at rest carrying the tangential
/// velocity is the same boundary as the moving wall, without markers that travel and
/// wrap: two such walls at `+U` and `-U` make plane Couette flow,
/// `u(z) = U (2 z / H - 1)` between walls at `z = 0` and `z = H`, wall shear stress
/// `tau = mu 2 U / H` (e.g. Batchelor 1967, *An Introduction to Fluid Dynamics*, sec. 4.2).
/// The velocity must be tangential to the group's walls (checked when the system is
/// built: an error names the group). Rigid and point carriers' markers are not affected.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct WallBelt {
    /// The wall group (e.g. `group_base + face` of
    /// [`SphBuilder::add_tank`](crate::SphBuilder::add_tank)).
    pub group: u16,
    /// The tangential velocity of the wall, m/s.
    pub velocity: [f64; 3],
}

impl ActiveDomain {
    /// `radius = supports` kernel supports (`2 h` each) of `settings`, `margin` one support.
    pub fn from_supports(settings: &SphSettings, supports: f64) -> Self {
        Self::from_radius(settings, supports * 2.0 * settings.h())
    }

    /// `radius` (m, a length of the flow: the same reach at every resolution), `margin`
    /// one kernel support `2 h` of `settings`. The radius is checked when the system is
    /// built (at least `2 h`, else an error naming `settings.active_domain.radius`).
    pub fn from_radius(settings: &SphSettings, radius: f64) -> Self {
        Self {
            radius,
            margin: 2.0 * settings.h(),
        }
    }
}

/// Settings of an [`SphSystem`](crate::SphSystem). SI units throughout.
///
/// Defaults: water (`rho_0 = 1000`, `mu = 1e-3`), Wendland C2 with `h = 1.5 dp`, Tait
/// `gamma = 7`, XSPH `zeta = 0.5`, density diffusion [`DensityDiffusion::Fourtakas`] with
/// `delta = 0.1`, Monaghan artificial viscosity `alpha = 0.02`, no Shepard filter, linear
/// no-slip extrapolation ([`NoSlip::Linear`]), re-sort by cell every 10 steps, Verlet
/// skin 10 % of the support, CFL 0.2, force criterion 0.25, viscous criterion 0.125,
/// gravity `(0, 0, -9.81)`. `spacing`, `sound_speed` and the domain must be set by the
/// caller.
///
/// Why `h = 1.5 dp` (not 1.3): particles start on a cubic lattice, and under pressure
/// the lattice has a shear stiffness (columns sliding past each other) whose sign
/// depends on the kernel and `h / dp`. Measured with Wendland C2 under hydrostatic
/// pressure (one column shifted by `0.02 dp`, `docs/validation-sph.md`): the force is
/// anti-restoring at `h / dp = 1.2, 1.3, 1.7` and restoring at 1.5 and 2.0; at 1.3 still
/// water is unstable (convection cells growing at ~7/s from the corner transients). At
/// 1.5 the lattice sum of the SPH Laplacian is also exact to 0.06 % (2.1 % low at 1.3,
/// which made viscous flows 2-3 % too fast at every resolution).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SphSettings {
    /// Initial particle spacing `dp`, m.
    pub spacing: f64,
    /// Smoothing length over spacing, `h / dp` (support `2 h`).
    pub h_over_dp: f64,
    /// Smoothing kernel.
    pub kernel: KernelKind,
    /// Reference density `rho_0`, kg/m^3.
    pub rho0: f64,
    /// Tait exponent `gamma`.
    pub gamma: f64,
    /// Artificial sound speed `c_s`, m/s (see [`sound_speed_for`](crate::sound_speed_for)).
    pub sound_speed: f64,
    /// Dynamic viscosity `mu`, Pa s (Morris term).
    pub viscosity: f64,
    /// Monaghan artificial viscosity `alpha` (Monaghan, Annu. Rev. Astron. Astrophys. 30
    /// (1992) 543-574; 0 = off; 0.01 to 0.05 is usual in WCSPH, Chrono uses 0.02-0.03):
    /// damps the acoustic noise and the free-surface waves of the start-up transient. It
    /// adds a viscosity `~ alpha c_s h / 10` (m^2/s), so set it to 0 for resolved viscous
    /// flows (Poiseuille).
    pub artificial_viscosity: f64,
    /// XSPH coefficient `zeta` (0 = off).
    pub xsph: f64,
    /// The density diffusion term of the continuity equation (delta-SPH).
    pub density_diffusion: DensityDiffusion,
    /// Its coefficient `delta` (dimensionless; 0.1 is the standard value of Molteni and
    /// Colagrossi 2009 and Antuono et al. 2010; 0 = off).
    pub diffusion_delta: f64,
    /// Shepard density re-initialization every this many steps (0 = never; an older
    /// alternative to density diffusion: with a free surface it biases the density of the
    /// surface particles, whose kernel is truncated).
    pub shepard_every: u32,
    /// The wall no-slip velocity extrapolation.
    pub no_slip: NoSlip,
    /// Re-sort particle arrays by cell at a neighbour-list rebuild when at least this
    /// many steps passed since the last re-sort (0 = never).
    pub reorder_every: u32,
    /// Verlet skin as a fraction of the kernel support: lists hold the pairs within
    /// `2 h (1 + skin)` and are rebuilt only when some particle moved more than half the
    /// skin since the last build (0 = rebuild every step).
    pub skin: f64,
    /// Courant number of `dt <= C h / (c_s + |v|_max)`.
    pub cfl: f64,
    /// Coefficient of the force criterion `dt <= C sqrt(h / |a|_max)`.
    pub force_coef: f64,
    /// Coefficient of the viscous criterion `dt <= C h^2 rho_0 / mu`.
    pub visc_coef: f64,
    /// Upper bound of the time step, s.
    pub max_dt: f64,
    /// Gravity, m/s^2.
    pub gravity: [f64; 3],
    /// Extra body force per unit mass on the fluid, m/s^2 (e.g. a driving pressure
    /// gradient in a periodic channel).
    pub body_force: [f64; 3],
    /// Lower corner of the domain, m (the grid box; periodic axes use it as the period).
    pub domain_lower: [f64; 3],
    /// Upper corner of the domain, m.
    pub domain_upper: [f64; 3],
    /// Periodic axes.
    pub periodic: [bool; 3],
    /// Clamp the extrapolated wall pressure at 0 so walls never pull the fluid (no
    /// sticking to walls under tension).
    pub clamp_wall_pressure: bool,
    /// Velocity damping rate `k` (1/s) of the fluid, `dv/dt += -k v`: 0 for physics;
    /// positive only for an initial relaxation phase that settles a lattice start
    /// (see [`SphSystem::set_damping`](crate::SphSystem::set_damping)).
    pub damping: f64,
    /// The Mach number limit (0.1).
    pub mach_limit: f64,
    /// What to do above it.
    pub mach_policy: MachPolicy,
    /// Step only the fluid near the moving bodies ([`ActiveDomain`]); `None` (the
    /// default) steps every particle.
    #[serde(default)]
    pub active_domain: Option<ActiveDomain>,
    /// Particle shifting after each step ([`Shifting`]); `None` (the default): none.
    #[serde(default)]
    pub shifting: Option<Shifting>,
    /// Tank walls that move along themselves ([`WallBelt`]); empty (the default): none.
    #[serde(default)]
    pub wall_belts: Vec<WallBelt>,
    /// A through-flow channel with a velocity inlet and a zero-gradient outlet along a
    /// non-periodic axis ([`OpenChannel`](crate::OpenChannel)); `None` (the default): none.
    #[serde(default)]
    pub open_channel: Option<crate::OpenChannel>,
}

impl Default for SphSettings {
    fn default() -> Self {
        Self {
            spacing: 0.01,
            h_over_dp: 1.5,
            kernel: KernelKind::WendlandC2,
            rho0: 1000.0,
            gamma: 7.0,
            sound_speed: 20.0,
            viscosity: 1e-3,
            artificial_viscosity: 0.02,
            xsph: 0.5,
            density_diffusion: DensityDiffusion::Fourtakas,
            diffusion_delta: 0.1,
            shepard_every: 0,
            no_slip: NoSlip::Linear,
            reorder_every: 10,
            skin: 0.1,
            cfl: 0.2,
            force_coef: 0.25,
            visc_coef: 0.125,
            max_dt: 1e-2,
            gravity: [GRAVITY.x, GRAVITY.y, GRAVITY.z],
            body_force: [0.0; 3],
            domain_lower: [0.0; 3],
            domain_upper: [1.0; 3],
            periodic: [false; 3],
            clamp_wall_pressure: true,
            damping: 0.0,
            mach_limit: 0.1,
            mach_policy: MachPolicy::Warn,
            active_domain: None,
            shifting: None,
            wall_belts: Vec::new(),
            open_channel: None,
        }
    }
}

impl SphSettings {
    /// The smoothing length `h = h_over_dp * spacing`, m.
    pub fn h(&self) -> f64 {
        self.h_over_dp * self.spacing
    }

    /// Checks every field; the error names the first bad one.
    pub fn validate(&self) -> Result<()> {
        positive("settings.spacing", self.spacing)?;
        positive("settings.h_over_dp", self.h_over_dp)?;
        if !(0.5..=3.0).contains(&self.h_over_dp) {
            return Err(SphError::invalid(
                "settings.h_over_dp",
                self.h_over_dp,
                "must be in [0.5, 3]",
            ));
        }
        positive("settings.rho0", self.rho0)?;
        positive("settings.gamma", self.gamma)?;
        positive("settings.sound_speed", self.sound_speed)?;
        non_negative("settings.viscosity", self.viscosity)?;
        non_negative("settings.artificial_viscosity", self.artificial_viscosity)?;
        non_negative("settings.xsph", self.xsph)?;
        non_negative("settings.diffusion_delta", self.diffusion_delta)?;
        if self.diffusion_delta > 1.0 {
            return Err(SphError::invalid(
                "settings.diffusion_delta",
                self.diffusion_delta,
                "must be in [0, 1]",
            ));
        }
        if self.xsph > 1.0 {
            return Err(SphError::invalid(
                "settings.xsph",
                self.xsph,
                "must be in [0, 1]",
            ));
        }
        non_negative("settings.skin", self.skin)?;
        if self.skin > 1.0 {
            return Err(SphError::invalid(
                "settings.skin",
                self.skin,
                "must be in [0, 1]",
            ));
        }
        positive("settings.cfl", self.cfl)?;
        positive("settings.force_coef", self.force_coef)?;
        positive("settings.visc_coef", self.visc_coef)?;
        positive("settings.max_dt", self.max_dt)?;
        positive("settings.mach_limit", self.mach_limit)?;
        non_negative("settings.damping", self.damping)?;
        if let Some(a) = &self.active_domain {
            let support = 2.0 * self.h();
            if !(a.radius.is_finite() && a.radius >= support * (1.0 - 1e-12)) {
                return Err(SphError::invalid(
                    "settings.active_domain.radius",
                    a.radius,
                    format!("must be finite and at least the kernel support 2 h = {support} m"),
                ));
            }
            if !(a.margin.is_finite() && a.margin >= 0.0) {
                return Err(SphError::invalid(
                    "settings.active_domain.margin",
                    a.margin,
                    "must be finite and >= 0",
                ));
            }
        }
        if let Some(sh) = &self.shifting
            && !(sh.coefficient.is_finite() && sh.coefficient > 0.0)
        {
            return Err(SphError::invalid(
                "settings.shifting.coefficient",
                sh.coefficient,
                "must be finite and > 0",
            ));
        }
        for (k, b) in self.wall_belts.iter().enumerate() {
            finite3(&format!("settings.wall_belts[{k}].velocity"), b.velocity)?;
            if self.wall_belts[..k].iter().any(|o| o.group == b.group) {
                return Err(SphError::invalid(
                    format!("settings.wall_belts[{k}].group"),
                    b.group,
                    "a group has one belt velocity",
                ));
            }
        }
        if let Some(oc) = &self.open_channel {
            oc.validate(
                self.domain_lower,
                self.domain_upper,
                self.periodic,
                2.0 * self.h(),
                self.gravity,
            )?;
        }
        finite3("settings.gravity", self.gravity)?;
        finite3("settings.body_force", self.body_force)?;
        finite3("settings.domain_lower", self.domain_lower)?;
        finite3("settings.domain_upper", self.domain_upper)?;
        for a in 0..3 {
            if self.domain_upper[a] <= self.domain_lower[a] {
                return Err(SphError::invalid(
                    format!("settings.domain_upper[{a}]"),
                    self.domain_upper[a],
                    format!("must exceed domain_lower[{a}] = {}", self.domain_lower[a]),
                ));
            }
            let len = self.domain_upper[a] - self.domain_lower[a];
            if self.periodic[a] && len < 4.0 * self.h() * (1.0 + self.skin) - 1e-12 * len {
                return Err(SphError::invalid(
                    format!("settings.periodic[{a}] (period)"),
                    len,
                    format!(
                        "the period must be at least twice the list radius, 4 h (1 + skin) = {}",
                        4.0 * self.h() * (1.0 + self.skin)
                    ),
                ));
            }
        }
        Ok(())
    }
}
