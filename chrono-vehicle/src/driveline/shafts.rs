//! One-dof rotational shafts in the system's CCP: gears, planetary gears and
//! differentials, clutches (locking, limited slip, brakes) and couplings to rigid bodies.
//!
//! A [`ShaftSystem`] is a [`PhysicsItem`]: each shaft is a 1-dof variable block (its spin
//! speed `w`, rad/s, with its polar inertia `J`, kg m^2, a
//! [`MassOperator::Scalar`]) and each link is a constraint row solved in the same cone
//! complementarity problem as the bodies, joints and contacts. Rows are velocity-level
//! (`D'v + b = 0`, no position stabilization: shaft angles are integrated speeds and only
//! reported). The rows (`c` are the row's coefficients on the shaft speeds):
//!
//! | link | row | multiplier |
//! |---|---|---|
//! | gear `a, b, r` | `w_a - r w_b = 0` | free |
//! | planetary `a, b, c` | `c_a w_a + c_b w_b + c_c w_c = 0` (Willis) | free |
//! | differential `carrier, l, r` | `w_c - (w_l + w_r)/2 = 0` | free |
//! | clutch `a, b` (or `a` to ground) | `w_a - w_b = 0` (`w_a = 0`) | `abs(g) <= T_max h` |
//! | speed motor `a` | `w_a - w_set = 0` | `abs(g) <= T_max h` |
//! | body coupling | `w_s - a . (omega_body - omega_ref) = 0` | free |
//!
//! The impulse `g` (N m s) of a row applies the torque `c_k g / h` to each shaft `k` of the
//! row; [`ShaftSystem::reaction`] reports `g / h` (N m), the torque on the row's first
//! shaft divided by its coefficient 1. A clutch whose limit is `T_max` either holds
//! (`abs(g/h) < T_max`, the shafts turn together) or slips and transmits exactly `T_max`
//! against the relative speed: this is a locking differential, a limited-slip clutch or,
//! to ground, a brake.
//!
//! A speed motor is a clutch to a reference turning at `w_set` (a hydrostatic motor whose
//! displacement sets its speed, with a relief valve limiting its torque): it holds the
//! shaft at `w_set` while the torque it needs stays within `T_max`, and gives exactly
//! `T_max` otherwise. Its reaction `g/h` is the torque it applies to the shaft, so its
//! power is `g/h * w_a`.
//!
//! A body coupling ties a shaft to a rigid body's spin about an axis `a` fixed in the
//! body frame (e.g. a wheel spindle's spin axis), relative to an optional reference body
//! (the chassis, standing for the axle housing): the reaction torque `-g/h` acts on the
//! body about `a` (world) and `+g/h` on the reference about the same world axis, so the
//! coupling conserves angular momentum. Fixed and kinematic bodies have no variables: their
//! known spin goes into the row's right-hand side.
//!
//! Applied torques ([`ShaftSystem::set_torque`]: engine, torque converter) enter the
//! momentum `k = J w + h T`. Links can be disabled (a gearbox in neutral) and re-enabled;
//! gear ratios and clutch limits can change every step (rows are rebuilt each step).
//! After the first step nothing is allocated.
//!
//! Reference: the shaft elements of Project Chrono (`ChShaft`, `ChShaftsGear`,
//! `ChShaftsPlanetary`, `ChShaftsClutch`, `ChShaftBodyRotation`), as summarized in our
//! notes; the formulation here (rows in the CCP) is our own.

use chrono_core::body::BodyHandle;
use chrono_core::descriptor::{
    BlockId, CcpProblem, ConstraintRows, MassOperator, RowEntry, RowId, Variables,
};
use chrono_core::item::{PhysicsItem, StepContext};
use chrono_core::math::Vector3;
use chrono_core::{ChronoError, Result as CoreResult};

use crate::error::{Result, VehicleError, check_finite, check_non_negative, check_positive};

/// Handle of a shaft in a [`ShaftSystem`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ShaftId(u32);

impl ShaftId {
    /// The shaft's index in its system (order of creation).
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// Handle of a link (gear, planetary, clutch, body coupling) in a [`ShaftSystem`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct LinkId(u32);

impl LinkId {
    /// The link's index in its system (order of creation).
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// What a link constrains (see the table in the [module docs](self)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LinkKind {
    /// `w_a - ratio w_b = 0`.
    Gear {
        /// Output shaft (coefficient 1).
        a: ShaftId,
        /// Input shaft (coefficient `-ratio`).
        b: ShaftId,
        /// Speed ratio `w_a / w_b`.
        ratio: f64,
    },
    /// `c[0] w_0 + c[1] w_1 + c[2] w_2 = 0` (Willis' equation of a planetary gear).
    Planetary {
        /// The three shafts.
        shafts: [ShaftId; 3],
        /// Their coefficients.
        coefs: [f64; 3],
    },
    /// `w_a - w_b = 0` (or `w_a = 0` with no `b`) with `abs(torque) <= max_torque`.
    Clutch {
        /// First shaft.
        a: ShaftId,
        /// Second shaft, or `None` for a brake to ground.
        b: Option<ShaftId>,
        /// Torque the clutch can transmit, N m (>= 0; 0 is disengaged).
        max_torque: f64,
    },
    /// `w_a - speed = 0` with `abs(torque) <= max_torque`: a speed-controlled motor.
    Motor {
        /// The driven shaft.
        a: ShaftId,
        /// Commanded speed, rad/s.
        speed: f64,
        /// Torque the motor can give, N m (>= 0; 0 is off).
        max_torque: f64,
    },
    /// `w_shaft - axis . (omega_body - omega_reference) = 0`.
    Body {
        /// The shaft.
        shaft: ShaftId,
        /// The body whose spin drives the shaft.
        body: BodyHandle,
        /// Unit axis in the body frame.
        axis: Vector3<f64>,
        /// Reference body (housing) taking the reaction, or `None` (ground).
        reference: Option<BodyHandle>,
    },
}

#[derive(Debug, Clone)]
struct Shaft {
    name: String,
    inertia: f64,
    angle: f64,
    speed: f64,
    torque: f64,
    block: Option<BlockId>,
}

#[derive(Debug, Clone)]
struct Link {
    kind: LinkKind,
    enabled: bool,
    row: Option<RowId>,
    impulse: f64,
    reaction: f64,
}

/// A set of 1-dof shafts and the links between them and to rigid bodies, stepped as a
/// [`PhysicsItem`] of a [`System`](chrono_core::System) (see the [module docs](self)).
///
/// ```
/// use chrono_vehicle::driveline::ShaftSystem;
/// let mut s = ShaftSystem::new("driveline");
/// let a = s.add_shaft("input", 0.5).unwrap();
/// let b = s.add_shaft("output", 2.0).unwrap();
/// let gear = s.add_gear(b, a, 0.25).unwrap(); // w_b = 0.25 w_a
/// s.set_torque(a, 100.0).unwrap();
/// // sys.add_item(Box::new(s)); then each step: sys.item_mut::<ShaftSystem>(i)
/// # let _ = gear;
/// ```
#[derive(Debug, Clone)]
pub struct ShaftSystem {
    name: String,
    shafts: Vec<Shaft>,
    links: Vec<Link>,
    /// Step size of the current step (set in `add_constraints`), s.
    h_step: f64,
}

impl ShaftSystem {
    /// An empty shaft system; `name` appears in messages.
    pub fn new(name: impl Into<String>) -> Self {
        Self {
            name: name.into(),
            shafts: Vec::new(),
            links: Vec::new(),
            h_step: 0.0,
        }
    }

    /// Add a shaft at rest of polar inertia `inertia` (kg m^2, finite and > 0).
    pub fn add_shaft(&mut self, name: impl Into<String>, inertia: f64) -> Result<ShaftId> {
        let name = name.into();
        check_positive(&format!("shaft \"{name}\".inertia"), inertia)?;
        self.shafts.push(Shaft {
            name,
            inertia,
            angle: 0.0,
            speed: 0.0,
            torque: 0.0,
            block: None,
        });
        Ok(ShaftId((self.shafts.len() - 1) as u32))
    }

    /// Add a gear pair `w_a = ratio w_b` (`ratio` finite and nonzero; negative reverses).
    /// Its reaction is the torque on `a`; `b` receives `-ratio` times it.
    pub fn add_gear(&mut self, a: ShaftId, b: ShaftId, ratio: f64) -> Result<LinkId> {
        self.check_shafts("gear", &[a, b])?;
        check_ratio("gear.ratio", ratio)?;
        Ok(self.push_link(LinkKind::Gear { a, b, ratio }))
    }

    /// Add a planetary gear `coefs[0] w_0 + coefs[1] w_1 + coefs[2] w_2 = 0` (Willis: for
    /// an ordinary ratio `t0` between shafts 0 and 1 with carrier 2, `coefs = [1, -t0, t0 - 1]`).
    pub fn add_planetary(&mut self, shafts: [ShaftId; 3], coefs: [f64; 3]) -> Result<LinkId> {
        self.check_shafts("planetary", &shafts)?;
        for (i, c) in coefs.iter().enumerate() {
            check_finite(&format!("planetary.coefs[{i}]"), *c)?;
        }
        if coefs.iter().all(|c| *c == 0.0) {
            return Err(VehicleError::invalid(
                "planetary.coefs",
                format!("{coefs:?}"),
                "at least one coefficient must be nonzero",
            ));
        }
        Ok(self.push_link(LinkKind::Planetary { shafts, coefs }))
    }

    /// Add an open bevel differential: the carrier (differential box) turns at the mean of
    /// the two outputs, `w_c - (w_l + w_r)/2 = 0`. Its reaction `g/h` is the torque on the
    /// carrier; each output receives `-1/2` of it (equal torque split).
    pub fn add_differential(
        &mut self,
        carrier: ShaftId,
        left: ShaftId,
        right: ShaftId,
    ) -> Result<LinkId> {
        self.add_planetary([carrier, left, right], [1.0, -0.5, -0.5])
    }

    /// Add a clutch between `a` and `b` (or a brake from `a` to ground with `b = None`) that
    /// transmits at most `max_torque` (N m, finite and >= 0; 0 is disengaged). Change the
    /// limit any step with [`set_clutch_torque`](Self::set_clutch_torque).
    pub fn add_clutch(
        &mut self,
        a: ShaftId,
        b: Option<ShaftId>,
        max_torque: f64,
    ) -> Result<LinkId> {
        match b {
            Some(b) => self.check_shafts("clutch", &[a, b])?,
            None => self.check_shafts("clutch", &[a])?,
        }
        check_non_negative("clutch.max_torque", max_torque)?;
        Ok(self.push_link(LinkKind::Clutch { a, b, max_torque }))
    }

    /// Add a speed motor on `a`: it holds `w_a = speed` (rad/s, finite) with at most
    /// `max_torque` (N m, finite and >= 0; 0 is off). Change both any step with
    /// [`set_motor`](Self::set_motor).
    pub fn add_motor(&mut self, a: ShaftId, speed: f64, max_torque: f64) -> Result<LinkId> {
        self.check_shafts("motor", &[a])?;
        check_finite("motor.speed", speed)?;
        check_non_negative("motor.max_torque", max_torque)?;
        Ok(self.push_link(LinkKind::Motor {
            a,
            speed,
            max_torque,
        }))
    }

    /// Set a speed motor's commanded speed (rad/s, finite) and torque limit (N m, finite
    /// and >= 0).
    pub fn set_motor(&mut self, link: LinkId, speed: f64, max_torque: f64) -> Result<()> {
        check_finite("motor.speed", speed)?;
        check_non_negative("motor.max_torque", max_torque)?;
        match &mut self.link_mut(link)?.kind {
            LinkKind::Motor {
                speed: w,
                max_torque: t,
                ..
            } => {
                *w = speed;
                *t = max_torque;
                Ok(())
            }
            other => Err(not_a("motor", link, other)),
        }
    }

    /// Couple `shaft` to the spin of `body` about `axis` (body frame, normalized here),
    /// relative to `reference` (e.g. the chassis; `None` is the ground):
    /// `w_shaft = a . (omega_body - omega_reference)` with `a = R_body axis` in the world.
    pub fn couple_to_body(
        &mut self,
        shaft: ShaftId,
        body: BodyHandle,
        axis: Vector3<f64>,
        reference: Option<BodyHandle>,
    ) -> Result<LinkId> {
        self.check_shafts("body coupling", &[shaft])?;
        let n = axis.norm();
        if !(n.is_finite() && n > 1e-12) {
            return Err(VehicleError::invalid(
                "body coupling.axis",
                format!("{:?}", axis.as_slice()),
                "must be finite and nonzero",
            ));
        }
        if reference == Some(body) {
            return Err(VehicleError::invalid(
                "body coupling.reference",
                body,
                "must differ from the coupled body",
            ));
        }
        Ok(self.push_link(LinkKind::Body {
            shaft,
            body,
            axis: axis / n,
            reference,
        }))
    }

    /// Set the torque limit of a clutch (N m, finite and >= 0), e.g. brake pedal times the
    /// brake's maximum torque, or a differential lock on (limit) / off (0).
    pub fn set_clutch_torque(&mut self, link: LinkId, max_torque: f64) -> Result<()> {
        check_non_negative("clutch.max_torque", max_torque)?;
        match &mut self.link_mut(link)?.kind {
            LinkKind::Clutch { max_torque: t, .. } => {
                *t = max_torque;
                Ok(())
            }
            other => Err(not_a("clutch", link, other)),
        }
    }

    /// Set the ratio of a gear (finite, nonzero): a gearbox shifting.
    pub fn set_gear_ratio(&mut self, link: LinkId, ratio: f64) -> Result<()> {
        check_ratio("gear.ratio", ratio)?;
        match &mut self.link_mut(link)?.kind {
            LinkKind::Gear { ratio: r, .. } => {
                *r = ratio;
                Ok(())
            }
            other => Err(not_a("gear", link, other)),
        }
    }

    /// Enable or disable a link (a disabled link adds no row: a gearbox in neutral).
    pub fn set_link_enabled(&mut self, link: LinkId, enabled: bool) -> Result<()> {
        let l = self.link_mut(link)?;
        l.enabled = enabled;
        if !enabled {
            l.impulse = 0.0;
            l.reaction = 0.0;
        }
        Ok(())
    }

    /// Set the applied torque on a shaft (N m, finite), acting every step until changed.
    pub fn set_torque(&mut self, shaft: ShaftId, torque: f64) -> Result<()> {
        self.check_state_value(shaft, "torque", torque)?;
        self.shafts[shaft.index()].torque = torque;
        Ok(())
    }

    /// Set a shaft's speed (rad/s, finite): initial conditions.
    pub fn set_speed(&mut self, shaft: ShaftId, speed: f64) -> Result<()> {
        self.check_state_value(shaft, "speed", speed)?;
        self.shafts[shaft.index()].speed = speed;
        Ok(())
    }

    /// Speed of a shaft, rad/s. Panics if `shaft` is not from this system.
    pub fn speed(&self, shaft: ShaftId) -> f64 {
        self.shafts[shaft.index()].speed
    }

    /// Angle of a shaft (integrated speed since the start), rad.
    pub fn angle(&self, shaft: ShaftId) -> f64 {
        self.shafts[shaft.index()].angle
    }

    /// The applied torque of a shaft, N m.
    pub fn torque(&self, shaft: ShaftId) -> f64 {
        self.shafts[shaft.index()].torque
    }

    /// Polar inertia of a shaft, kg m^2.
    pub fn inertia(&self, shaft: ShaftId) -> f64 {
        self.shafts[shaft.index()].inertia
    }

    /// Name of a shaft.
    pub fn shaft_name(&self, shaft: ShaftId) -> &str {
        &self.shafts[shaft.index()].name
    }

    /// Number of shafts.
    pub fn n_shafts(&self) -> usize {
        self.shafts.len()
    }

    /// The ids of all shafts, in creation order.
    pub fn shaft_ids(&self) -> impl Iterator<Item = ShaftId> + use<> {
        (0..self.shafts.len() as u32).map(ShaftId)
    }

    /// What a link is, with its current ratio or limit.
    pub fn link(&self, link: LinkId) -> &LinkKind {
        &self.links[link.index()].kind
    }

    /// The reaction of a link in the last step, `g / h` (N m): the torque on the link's
    /// first shaft (gear `a`, planetary shaft 0, clutch `a`, the coupled shaft). 0 for a
    /// link without a row in that step (disabled, a disengaged clutch).
    pub fn reaction(&self, link: LinkId) -> f64 {
        self.links[link.index()].reaction
    }

    /// Kinetic energy of the shafts, `sum J w^2 / 2`, J.
    pub fn kinetic_energy(&self) -> f64 {
        self.shafts
            .iter()
            .map(|s| 0.5 * s.inertia * s.speed * s.speed)
            .sum()
    }

    fn push_link(&mut self, kind: LinkKind) -> LinkId {
        self.links.push(Link {
            kind,
            enabled: true,
            row: None,
            impulse: 0.0,
            reaction: 0.0,
        });
        LinkId((self.links.len() - 1) as u32)
    }

    fn shaft(&self, id: ShaftId) -> Result<&Shaft> {
        self.shafts.get(id.index()).ok_or_else(|| {
            VehicleError::invalid(
                format!("shaft system \"{}\": shaft id", self.name),
                id.index(),
                format!("only {} shafts", self.shafts.len()),
            )
        })
    }

    /// A finite value for a shaft's state (formats the field name only on error: the
    /// setters run every step).
    fn check_state_value(&self, shaft: ShaftId, what: &str, value: f64) -> Result<()> {
        let s = self.shaft(shaft)?;
        if value.is_finite() {
            Ok(())
        } else {
            check_finite(&format!("shaft \"{}\".{what}", s.name), value).map(|_| ())
        }
    }

    fn link_mut(&mut self, id: LinkId) -> Result<&mut Link> {
        let n = self.links.len();
        let name = &self.name;
        self.links.get_mut(id.index()).ok_or_else(|| {
            VehicleError::invalid(
                format!("shaft system \"{name}\": link id"),
                id.index(),
                format!("only {n} links"),
            )
        })
    }

    fn check_shafts(&self, what: &str, ids: &[ShaftId]) -> Result<()> {
        for (i, id) in ids.iter().enumerate() {
            self.shaft(*id)?;
            if ids[..i].contains(id) {
                return Err(VehicleError::invalid(
                    format!("{what}: shaft {i}"),
                    format!("\"{}\"", self.shafts[id.index()].name),
                    "a link needs distinct shafts",
                ));
            }
        }
        Ok(())
    }

    fn block(&self, s: ShaftId) -> BlockId {
        self.shafts[s.index()]
            .block
            .expect("shaft blocks are added before rows")
    }

    fn label(&self) -> String {
        format!("shaft system \"{}\"", self.name)
    }
}

fn check_ratio(field: &str, ratio: f64) -> Result<()> {
    if ratio.is_finite() && ratio != 0.0 {
        Ok(())
    } else {
        Err(VehicleError::invalid(
            field,
            ratio,
            "must be finite and nonzero",
        ))
    }
}

fn not_a(what: &str, link: LinkId, kind: &LinkKind) -> VehicleError {
    VehicleError::invalid(
        format!("link {}", link.index()),
        format!("{kind:?}"),
        format!("is not a {what}"),
    )
}

/// A row entry on a shaft block with the coefficient `c` (1 dof).
fn entry(block: BlockId, c: &[f64]) -> RowEntry<'_> {
    RowEntry { block, coefs: c }
}

impl PhysicsItem for ShaftSystem {
    fn name(&self) -> &str {
        &self.name
    }

    fn add_variables(&mut self, vars: &mut Variables) {
        for s in &mut self.shafts {
            // The inertia was checked > 0 when the shaft was added.
            s.block = Some(vars.add(MassOperator::Scalar { mass: s.inertia }));
        }
    }

    /// `k = J w + h T` for every shaft.
    fn load_momentum(&self, ctx: &StepContext, vars: &Variables, k: &mut [f64]) {
        for s in &self.shafts {
            if let Some(b) = s.block {
                k[vars.offset(b)] += s.inertia * s.speed + ctx.h * s.torque;
            }
        }
    }

    /// Gear, planetary and clutch rows (body couplings come in
    /// [`add_body_constraints`](PhysicsItem::add_body_constraints)).
    fn add_constraints(
        &mut self,
        ctx: &StepContext,
        _vars: &Variables,
        rows: &mut ConstraintRows,
    ) -> CoreResult<()> {
        self.h_step = ctx.h;
        for li in 0..self.links.len() {
            let link = &self.links[li];
            let row = if !link.enabled {
                None
            } else {
                match link.kind {
                    LinkKind::Gear { a, b, ratio } => {
                        let (ca, cb) = ([1.0], [-ratio]);
                        let e = [entry(self.block(a), &ca), entry(self.block(b), &cb)];
                        Some(rows.push_bilateral(&e, 0.0, 0.0))
                    }
                    LinkKind::Planetary { shafts, coefs } => {
                        let c = coefs.map(|c| [c]);
                        let e = [
                            entry(self.block(shafts[0]), &c[0]),
                            entry(self.block(shafts[1]), &c[1]),
                            entry(self.block(shafts[2]), &c[2]),
                        ];
                        Some(rows.push_bilateral(&e, 0.0, 0.0))
                    }
                    LinkKind::Clutch {
                        max_torque: 0.0, ..
                    } => None,
                    LinkKind::Clutch { a, b, max_torque } => {
                        let (ca, cb) = ([1.0], [-1.0]);
                        let lim = max_torque * ctx.h;
                        let ea = entry(self.block(a), &ca);
                        Some(match b {
                            Some(b) => {
                                let e = [ea, entry(self.block(b), &cb)];
                                rows.push_box(&e, 0.0, 0.0, -lim, lim)
                            }
                            None => rows.push_box(&[ea], 0.0, 0.0, -lim, lim),
                        })
                    }
                    LinkKind::Motor {
                        max_torque: 0.0, ..
                    } => None,
                    LinkKind::Motor {
                        a,
                        speed,
                        max_torque,
                    } => {
                        let ca = [1.0];
                        let lim = max_torque * ctx.h;
                        let e = [entry(self.block(a), &ca)];
                        Some(rows.push_box(&e, -speed, 0.0, -lim, lim))
                    }
                    LinkKind::Body { .. } => continue,
                }
            };
            self.links[li].row = row;
        }
        Ok(())
    }

    /// Body-coupling rows: `w_s - a.(omega_body - omega_ref) = 0`, with the body's
    /// Jacobian on its 6-dof block (`[0; -axis]` in its frame) and the reference's
    /// (`[0; R_ref' a]`); a fixed or kinematic body's known spin goes into `b`.
    fn add_body_constraints(
        &mut self,
        _ctx: &StepContext,
        bodies: &chrono_core::Bodies,
        _vars: &Variables,
        rows: &mut ConstraintRows,
    ) -> CoreResult<()> {
        for li in 0..self.links.len() {
            let LinkKind::Body {
                shaft,
                body,
                axis,
                reference,
            } = self.links[li].kind
            else {
                continue;
            };
            if !self.links[li].enabled {
                self.links[li].row = None;
                continue;
            }
            let get = |h: BodyHandle, what: &str| {
                bodies.get(h).ok_or_else(|| ChronoError::UnknownHandle {
                    kind: "body",
                    index: h.index() as usize,
                    field: format!("{}: link {li} {what} ({h})", self.label()),
                })
            };
            let b = get(body, "body")?;
            let a_world = b.rotation() * axis;
            let jb = b.angular_jacobian(&(-a_world));
            let jr;
            let one = [1.0];
            let mut e = [entry(self.block(shaft), &one); 3];
            let mut n = 1;
            let mut rhs = 0.0;
            match b.block() {
                Some(blk) => {
                    e[n] = entry(blk, &jb);
                    n += 1;
                }
                None => rhs += b.jacobian_times_velocity(&jb),
            }
            if let Some(r) = reference {
                let rb = get(r, "reference")?;
                jr = rb.angular_jacobian(&a_world);
                match rb.block() {
                    Some(blk) => {
                        e[n] = entry(blk, &jr);
                        n += 1;
                    }
                    None => rhs += rb.jacobian_times_velocity(&jr),
                }
            }
            self.links[li].row = Some(rows.push_bilateral(&e[..n], rhs, 0.0));
        }
        Ok(())
    }

    /// Last step's impulses (a clutch's clamped to its current limit).
    fn warm_start(&self, problem: &CcpProblem, gamma: &mut [f64]) {
        for l in &self.links {
            if let Some(id) = l.row {
                let g = match l.kind {
                    LinkKind::Clutch { max_torque, .. } | LinkKind::Motor { max_torque, .. } => {
                        let lim = max_torque * self.h_step;
                        l.impulse.clamp(-lim, lim)
                    }
                    _ => l.impulse,
                };
                gamma[problem.row_index(id)] = g;
            }
        }
    }

    fn update(
        &mut self,
        ctx: &StepContext,
        vars: &Variables,
        v: &[f64],
        problem: &CcpProblem,
        gamma: &[f64],
    ) -> CoreResult<()> {
        for (i, s) in self.shafts.iter_mut().enumerate() {
            let Some(b) = s.block else { continue };
            s.speed = v[vars.offset(b)];
            s.angle += ctx.h * s.speed;
            if !(s.speed.is_finite() && s.angle.is_finite()) {
                return Err(ChronoError::NonFinite {
                    item: format!("shaft system \"{}\"", self.name),
                    step: ctx.step,
                    time: ctx.time,
                    what: format!("speed of shaft {i} (\"{}\")", s.name),
                });
            }
        }
        for l in &mut self.links {
            (l.impulse, l.reaction) = match l.row {
                Some(id) => {
                    let g = gamma[problem.row_index(id)];
                    (g, g / ctx.h)
                }
                None => (0.0, 0.0),
            };
        }
        Ok(())
    }
}
