//! The active domain of an [`SphSystem`] (set by
//! [`SphSettings::active_domain`](crate::SphSettings::active_domain)): only the fluid near
//! the moving bodies is stepped.
//!
//! **Sources and activity.** A source is a rigid or point marker carrier that moves
//! ([`SphSystem::set_carrier_source`]), bounded by a sphere: a rigid carrier's centre and
//! the largest body-frame offset of its markers; a point carrier's marker centroid and
//! the largest distance from it, at the current time. A fluid particle is *active* while
//! its distance to the nearest bounding sphere, `d(x) = min_s (|x - c_s| - r_s)`, is at
//! most [`ActiveDomain::radius`](crate::ActiveDomain::radius) (periodic axes: the
//! minimum image). The set is re-evaluated at every fluid step after the drift, at the
//! sources' new poses: a function of the positions only, so it is the same for any
//! thread count and slot order.
//!
//! **Frozen particles** (inactive fluid) keep their position, velocity and density bit
//! for bit; they are not kicked, drifted, filtered, nor evaluated (no neighbour row), and
//! they do not enter the time step criteria. They stay neighbours of the active
//! particles with their held state: the held velocity (not zero) in the continuity,
//! viscous and XSPH terms and the pressure of their held density, so the active fluid
//! sees a frozen region as fluid "stopped in time" at the state it had.
//!
//! **Entering and leaving, within the leapfrog** (`A_n`: the particles active during step
//! `n -> n+1`, `A_{n+1}` from the positions at `t_{n+1}`):
//!
//! - the first half kick and the drift move `A_n`;
//! - the evaluation at `t_{n+1}` (continuity, forces, wall extrapolation) covers
//!   `A_n ∪ A_{n+1}`; the density increment `dt d rho/dt` and the second half kick apply
//!   to `A_n` only, so a particle leaving the domain completes its step and freezes at a
//!   consistent leapfrog state;
//! - a particle entering at `t_{n+1}` starts the leapfrog there from its held state, as a
//!   particle does at `t = 0`: its position, velocity and density are those it froze with
//!   (no jump: nothing is reset, re-initialized or interpolated), its first derivatives
//!   are the ones evaluated at `t_{n+1}`, and its next step kicks with them. Its pressure
//!   is the Tait pressure of its held density, the value its neighbours have seen all
//!   along, so the pressure field is continuous across the activation too.
//!
//! **Neighbour rows.** List rows are built only for *listed* particles: fluid within
//! `radius + margin` of a source and wall markers within `radius + margin + r_list`
//! (`r_list` the list radius). Wall markers extrapolate their pressure only when listed;
//! the others hold theirs (they touch only frozen fluid). The list is rebuilt, besides
//! the Verlet criterion, when a particle of `A_n ∪ A_{n+1}` has no row or a source moved
//! (centre plus radius) more than `margin` since the last build: a wall within the
//! support of an evaluated particle is then always listed (`d` is 1-Lipschitz in the
//! position and in the source's centre and radius).
//!
//! **Off** (`active_domain: None`): every particle carries every flag and the passes read
//! no mask: the arithmetic is that of a system without the option, bit for bit. With a
//! radius that covers the whole tank every particle is active at every step and every
//! mask passes: the same bits again (`tests::active_domain_*`).

use rayon::prelude::*;

use super::SphSystem;
use crate::carrier::{NO_CARRIER, POINT_CARRIER};
use crate::data::FLUID;
use crate::error::{Result, SphError};
use crate::motion::WallMotion;

/// Flag: active during the current step (`A_n`; after a step, `A_{n+1}`).
pub(crate) const ACT_NOW: u8 = 1;
/// Flag: active at the end of the current step (`A_{n+1}`).
pub(crate) const ACT_NEXT: u8 = 2;
/// Flag: the particle has a neighbour row.
pub(crate) const LISTED: u8 = 4;
/// Every flag of a stepped particle: the state of every particle when the active domain
/// and the open channel are off.
pub(crate) const ALL: u8 = ACT_NOW | ACT_NEXT | LISTED;
/// Flag: a fluid particle in a buffer zone of the open channel ([`crate::open`]): moved
/// with its imposed velocity, never stepped (set with `ACT_NEXT` from the positions).
pub(crate) const BUFFER: u8 = 8;

/// The distance of `x` to the nearest source sphere `[cx, cy, cz, r]`, m (`+inf`
/// without sources).
#[inline]
fn distance(grid: &chrono_core::particles::CellGrid, sources: &[[f64; 4]], x: [f64; 3]) -> f64 {
    let mut d = f64::INFINITY;
    for s in sources {
        let e = grid.displacement(x, [s[0], s[1], s[2]]);
        d = d.min((e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt() - s[3]);
    }
    d
}

impl SphSystem {
    /// Whether the active domain is on.
    pub(super) fn active_on(&self) -> bool {
        self.settings.active_domain.is_some()
    }

    /// Marks rigid carrier `carrier` as a source of the active domain (`true`, the
    /// default: a carrier that moves) or not (a fixed body: the fluid near it is not
    /// stepped for its sake). A carrier that moves must stay a source: a non-source's
    /// markers are updated only where other sources make the fluid active. Errors: an
    /// unknown carrier.
    pub fn set_carrier_source(&mut self, carrier: usize, source: bool) -> Result<()> {
        let n = self.carrier_source.len();
        *self
            .carrier_source
            .get_mut(carrier)
            .ok_or_else(|| SphError::invalid("carrier", carrier, format!("only {n} carriers")))? =
            source;
        Ok(())
    }

    /// [`set_carrier_source`](Self::set_carrier_source) for point carrier `carrier`.
    pub fn set_point_carrier_source(&mut self, carrier: usize, source: bool) -> Result<()> {
        let n = self.point_source.len();
        *self.point_source.get_mut(carrier).ok_or_else(|| {
            SphError::invalid("point carrier", carrier, format!("only {n} point carriers"))
        })? = source;
        Ok(())
    }

    /// Whether the fluid particle in slot `i` is active (stepped) in the next step
    /// (always true with the active domain off; false for wall markers).
    pub fn is_active(&self, i: usize) -> bool {
        self.data.kind[i] == FLUID && self.act[i] & ACT_NOW != 0
    }

    /// The sources' bounding spheres `[cx, cy, cz, r]` (m) at the current time (see the
    /// [module docs](self)).
    pub fn active_sources(&self) -> &[[f64; 4]] {
        &self.sources
    }

    /// Errors of the active-domain set-up: moving tank walls (they move all the fluid)
    /// and no source (all the fluid would freeze).
    pub(super) fn check_active_domain(&self) -> Result<()> {
        if !self.active_on() {
            return Ok(());
        }
        if !matches!(self.motion, WallMotion::Fixed) {
            return Err(SphError::invalid(
                "settings.active_domain",
                "Some",
                "needs fixed tank walls (WallMotion::Fixed): a moving tank moves all the fluid",
            ));
        }
        let n = self.carrier_source.iter().filter(|&&s| s).count()
            + self.point_source.iter().filter(|&&s| s).count();
        if n == 0 {
            return Err(SphError::invalid(
                "settings.active_domain",
                "Some",
                "needs at least one moving marker carrier (a source): without one every fluid particle freezes",
            ));
        }
        Ok(())
    }

    /// The largest body-frame marker offset of every rigid carrier, m.
    pub(super) fn carrier_radii(&self) -> Vec<f64> {
        let d = &self.data;
        let mut r = vec![0.0f64; self.carriers.len()];
        for (&k, a) in d.carrier.iter().zip(&d.anchor) {
            if k != NO_CARRIER && k & POINT_CARRIER == 0 {
                let l = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
                r[k as usize] = r[k as usize].max(l);
            }
        }
        r
    }

    /// The sources' bounding spheres at the current time into `self.sources`.
    fn compute_sources(&mut self) {
        self.sources.clear();
        for (k, c) in self.carriers.iter().enumerate() {
            if self.carrier_source[k] {
                self.sources
                    .push([c.centre.x, c.centre.y, c.centre.z, self.carrier_radius[k]]);
            }
        }
        let t = self.time;
        for (k, c) in self.point_carriers.iter().enumerate() {
            if !self.point_source[k] || c.x0.is_empty() {
                continue;
            }
            // unwrapped positions x0 + (t - t0) v (the distance wraps periodic axes)
            let s = t - c.t0;
            let at = |i: usize| {
                let (x, v) = (c.x0[i], c.v[i]);
                [x[0] + s * v[0], x[1] + s * v[1], x[2] + s * v[2]]
            };
            let mut m = [0.0; 3];
            for i in 0..c.x0.len() {
                let p = at(i);
                m = [m[0] + p[0], m[1] + p[1], m[2] + p[2]];
            }
            let inv = 1.0 / c.x0.len() as f64;
            let m = [m[0] * inv, m[1] * inv, m[2] * inv];
            let mut r = 0.0f64;
            for i in 0..c.x0.len() {
                let p = at(i);
                let e = [p[0] - m[0], p[1] - m[1], p[2] - m[2]];
                r = r.max((e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt());
            }
            self.sources.push([m[0], m[1], m[2], r]);
        }
    }

    /// Sets the `ACT_NEXT` flag of every fluid particle from its distance to the sources
    /// at the current positions (active domain), and its `BUFFER` flag from its zone (open
    /// channel): a buffer particle is never active.
    pub(super) fn update_activity(&mut self) {
        let ad = self.settings.active_domain;
        let open = self.settings.open_channel;
        if ad.is_none() && open.is_none() {
            return;
        }
        if ad.is_some() {
            self.compute_sources();
        }
        let (lo, hi) = (self.settings.domain_lower, self.settings.domain_upper);
        let (grid, sources, d) = (&self.grid, &self.sources, &self.data);
        self.act.par_iter_mut().enumerate().for_each(|(i, a)| {
            if d.kind[i] != FLUID {
                return;
            }
            let x = [d.x[i], d.y[i], d.z[i]];
            let mut next = ad.is_none_or(|ad| distance(grid, sources, x) <= ad.radius);
            let buffer = open.is_some_and(|oc| {
                let k = oc.axis;
                oc.zone(x[k], lo[k], hi[k]) != crate::open::ZONE_FLUID
            });
            next &= !buffer;
            *a = (*a & !(ACT_NEXT | BUFFER))
                | if next { ACT_NEXT } else { 0 }
                | if buffer { BUFFER } else { 0 };
        });
    }

    /// `A_n := A_{n+1}` at the end of a step; returns the number of active fluid
    /// particles.
    pub(super) fn promote_activity(&mut self) -> usize {
        if !self.active_on() && self.settings.open_channel.is_none() {
            return self.n_fluid;
        }
        let d = &self.data;
        self.act
            .par_iter_mut()
            .enumerate()
            .map(|(i, a)| {
                *a = (*a & !ACT_NOW) | ((*a & ACT_NEXT) >> 1);
                (d.kind[i] == FLUID && *a & ACT_NOW != 0) as usize
            })
            .sum()
    }

    /// Whether the active domain needs a new neighbour list: an evaluated particle
    /// without a row, or a source moved more than the margin since the last build.
    pub(super) fn activity_needs_rebuild(&self) -> bool {
        let Some(ad) = self.settings.active_domain else {
            return false;
        };
        if self.sources.len() != self.list_sources.len() {
            return true;
        }
        for (s, b) in self.sources.iter().zip(&self.list_sources) {
            let e = self
                .grid
                .displacement([s[0], s[1], s[2]], [b[0], b[1], b[2]]);
            let moved = (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt() + (s[3] - b[3]).abs();
            if moved > ad.margin {
                return true;
            }
        }
        let d = &self.data;
        self.act
            .par_iter()
            .enumerate()
            .with_min_len(4096)
            .any(|(i, &a)| d.kind[i] == FLUID && a & (ACT_NOW | ACT_NEXT) != 0 && a & LISTED == 0)
    }

    /// Sets the `LISTED` flags at the current positions (before a list build) and keeps
    /// the sources of this build.
    pub(super) fn mark_listed(&mut self) {
        let Some(ad) = self.settings.active_domain else {
            return;
        };
        let (grid, sources, d) = (&self.grid, &self.sources, &self.data);
        let fluid_reach = ad.radius + ad.margin;
        let wall_reach = fluid_reach + self.list_radius;
        self.act.par_iter_mut().enumerate().for_each(|(i, a)| {
            let reach = if d.kind[i] == FLUID {
                fluid_reach
            } else {
                wall_reach
            };
            let listed = distance(grid, sources, [d.x[i], d.y[i], d.z[i]]) <= reach;
            *a = (*a & !LISTED) | if listed { LISTED } else { 0 };
        });
        self.list_sources.clear();
        self.list_sources.extend_from_slice(&self.sources);
    }
}
