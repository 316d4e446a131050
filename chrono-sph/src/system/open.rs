//! The open channel's buffers in the step of an [`SphSystem`] (the rules:
//! [`crate::open`]): the inflow velocity imposed on the inlet buffer, the pressure (both
//! buffers) and velocity (outlet) extrapolated from the fluid, and the exchange of
//! particles at the ends (the inlet's lattice rows fed, the outflow removed) at list
//! builds.

use rayon::prelude::*;

use chrono_core::particles::{CellGrid, Kernel, NeighborList};

use super::SphSystem;
use super::active::{BUFFER, LISTED};
use crate::data::{FLUID, Kind, ParticleData};
use crate::eos::Tait;
use crate::open::{OpenChannel, Outflow, ZONE_INLET, ZONE_OUTLET};
use crate::settings::SphSettings;

/// The open channel of `s`, its flow axis and the domain's bounds along it (m); `None`
/// without one.
fn open_axis(s: &SphSettings) -> Option<(OpenChannel, usize, f64, f64)> {
    let oc = s.open_channel?;
    let k = oc.axis;
    Some((oc, k, s.domain_lower[k], s.domain_upper[k]))
}

/// One lattice row of the inlet buffer: the section point it feeds.
#[derive(Debug, Clone, Copy)]
pub(crate) struct InletRow {
    /// The row's rear: its lateral coordinates, and along the axis where its last
    /// particle is (or would be), m.
    pub rear: [f64; 3],
    /// The mass of the row's particles, kg.
    pub mass: f64,
}

impl SphSystem {
    /// The inlet's lattice rows from the particles in the inlet buffer at the start: one
    /// per section point (lateral coordinates to a tenth of the spacing), its rear the
    /// lowest coordinate along the axis; and the first free id.
    pub(super) fn init_open_channel(&mut self) {
        let Some((oc, k, lo, hi)) = open_axis(&self.settings) else {
            return;
        };
        let d = &self.data;
        let q = 0.1 * self.settings.spacing;
        let mut rows = std::collections::BTreeMap::<(i64, i64), InletRow>::new();
        for i in 0..d.len() {
            let p = [d.x[i], d.y[i], d.z[i]];
            if d.kind[i] != FLUID || oc.zone(p[k], lo, hi) != ZONE_INLET {
                continue;
            }
            let (a, b) = ((k + 1) % 3, (k + 2) % 3);
            let key = ((p[a] / q).round() as i64, (p[b] / q).round() as i64);
            rows.entry(key)
                .and_modify(|r| {
                    if p[k] < r.rear[k] {
                        r.rear = p;
                    }
                })
                .or_insert(InletRow {
                    rear: p,
                    mass: d.mass[i],
                });
        }
        self.inlet_rows = rows.into_values().collect();
        self.next_id = d.id.iter().max().map_or(0, |&m| m + 1);
    }

    /// Moves the inlet rows' rears as their particles drift over `dt` (the velocity set
    /// at the current time, as the drift reads it).
    pub(super) fn advance_inlet_rows(&mut self, dt: f64) {
        let Some(oc) = self.settings.open_channel else {
            return;
        };
        let t = self.time;
        for r in &mut self.inlet_rows {
            r.rear[oc.axis] += dt * oc.inflow_speed(r.rear, t);
        }
    }

    /// The exchange at the ends, before a list build: particles past the domain's end
    /// removed, and every inlet row whose rear moved a spacing or more into the buffer
    /// fed one particle a spacing behind it (the row's lattice density, the inflow
    /// velocity, a new id).
    /// Returns whether the particle count changed.
    pub(super) fn open_exchange(&mut self) -> bool {
        let Some((oc, k, lo, hi)) = open_axis(&self.settings) else {
            return false;
        };
        let dp = self.settings.spacing;
        let d = &self.data;
        let coord = |i: usize| [d.x[i], d.y[i], d.z[i]][k];
        let gone = (0..d.len()).any(|i| d.kind[i] == FLUID && coord(i) >= hi);
        let mut changed = false;
        if gone {
            self.keep.clear();
            self.keep
                .extend((0..d.len()).map(|i| d.kind[i] != FLUID || coord(i) < hi));
            self.data.retain(&self.keep);
            let keep = &self.keep;
            let mut j = 0;
            self.act.retain(|_| {
                j += 1;
                keep[j - 1]
            });
            changed = true;
        }
        let t = self.time;
        let cell = dp * dp * dp;
        for r in &mut self.inlet_rows {
            // the row's lattice density (its particles fill their cells)
            let rho0 = r.mass / cell;
            // a small tolerance: a rear exactly a spacing in feeds now
            while r.rear[k] - dp >= lo - 1e-9 * dp {
                r.rear[k] -= dp;
                self.data.push(Kind::Fluid, r.rear, rho0, r.mass, 0);
                let i = self.data.len() - 1;
                self.data.id[i] = self.next_id;
                self.next_id += 1;
                let v = oc.inflow_velocity(r.rear, t);
                (self.data.vx[i], self.data.vy[i], self.data.vz[i]) = (v[0], v[1], v[2]);
                self.data.p[i] = self.eos.pressure(rho0);
                self.act.push(LISTED | BUFFER);
                changed = true;
            }
        }
        if changed {
            self.n_fluid = self.data.kind.iter().filter(|&&c| c == FLUID).count();
        }
        changed
    }

    /// Sets the velocity of every inlet-buffer particle to the inflow at its position and
    /// the current time (after the zones are updated; open channel only).
    pub(super) fn set_inflow(&mut self) {
        let Some((oc, k, lo, hi)) = open_axis(&self.settings) else {
            return;
        };
        let t = self.time;
        let act = &self.act;
        let d = &mut self.data;
        (
            d.vx.par_iter_mut(),
            d.vy.par_iter_mut(),
            d.vz.par_iter_mut(),
            d.x.par_iter(),
            d.y.par_iter(),
            d.z.par_iter(),
            act.par_iter(),
        )
            .into_par_iter()
            .for_each(|(vx, vy, vz, &x, &y, &z, &a)| {
                if a & BUFFER == 0 {
                    return;
                }
                let p = [x, y, z];
                if oc.zone(p[k], lo, hi) == ZONE_INLET {
                    let v = oc.inflow_velocity(p, t);
                    *vx = v[0];
                    *vy = v[1];
                    *vz = v[2];
                }
            });
    }

    /// The buffers' pressure (and density, by the equation of state) extrapolated from the
    /// fluid with a zero normal gradient, and the outlet's velocity likewise:
    /// `p_i = sum_f (p_f + rho_f b . (x_i - x_f)) W_if / sum_f W_if`,
    /// `v_i = sum_f v_f W_if / sum_f W_if` over the fluid-zone neighbours `f` (`b` the body
    /// acceleration: gravity plus the settings' body force, as for the wall markers). A
    /// buffer particle without fluid neighbours keeps its values. Reads the fluid's new
    /// densities and pressures: after the equation of state, before the force pass. (Parts
    /// of the system, not `self`: the density phase holds its pass context meanwhile.)
    #[allow(clippy::too_many_arguments)]
    pub(super) fn open_extrapolation(
        s: &SphSettings,
        kernel: &Kernel,
        eos: &Tait,
        grid: &CellGrid,
        list: &NeighborList,
        act: &[u8],
        d: &mut ParticleData,
        bc: &mut Vec<[f64; 5]>,
        time: f64,
    ) {
        let Some((oc, k, lo, hi)) = open_axis(s) else {
            return;
        };
        let b = [
            s.gravity[0] + s.body_force[0],
            s.gravity[1] + s.body_force[1],
            s.gravity[2] + s.body_force[2],
        ];
        let support2 = kernel.support() * kernel.support();
        bc.resize(d.len(), [0.0; 5]);
        {
            let d = &*d;
            bc.par_iter_mut().enumerate().for_each(|(i, out)| {
                *out = [0.0; 5];
                if d.kind[i] != FLUID || act[i] & BUFFER == 0 {
                    return;
                }
                let xi = [d.x[i], d.y[i], d.z[i]];
                let (mut sw, mut sp) = (0.0, 0.0);
                let mut sv = [0.0; 3];
                for &f in list.neighbors(i) {
                    let f = f as usize;
                    if d.kind[f] != FLUID || act[f] & BUFFER != 0 {
                        continue;
                    }
                    let e = grid.displacement(xi, [d.x[f], d.y[f], d.z[f]]);
                    let r2 = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
                    if r2 >= support2 {
                        continue; // W = 0: the list's skin
                    }
                    let wk = kernel.w(r2.sqrt());
                    sw += wk;
                    sp += (d.p[f] + d.rho[f] * (b[0] * e[0] + b[1] * e[1] + b[2] * e[2])) * wk;
                    sv[0] += d.vx[f] * wk;
                    sv[1] += d.vy[f] * wk;
                    sv[2] += d.vz[f] * wk;
                }
                if sw > 0.0 {
                    *out = [sw, sp / sw, sv[0] / sw, sv[1] / sw, sv[2] / sw];
                }
            });
        }
        // the absorbing outlet's impedance term from the outlet's mean axial velocity (a
        // serial sum: the same bits on any thread count)
        let p_out = match oc.outflow {
            Outflow::Pressure { p } => Some(p),
            Outflow::ZeroGradient => None,
            Outflow::Absorbing { p } => {
                let (mut su, mut n) = (0.0, 0usize);
                for (i, o) in bc.iter().enumerate() {
                    if o[0] > 0.0 && oc.zone([d.x[i], d.y[i], d.z[i]][k], lo, hi) == ZONE_OUTLET {
                        su += o[2 + k];
                        n += 1;
                    }
                }
                let u_out = if n > 0 { su / n as f64 } else { 0.0 };
                Some(p + s.rho0 * s.sound_speed * (u_out - oc.inflow_mean(time)))
            }
        };
        let cell = s.spacing * s.spacing * s.spacing;
        (
            (
                d.p.par_iter_mut(),
                d.rho.par_iter_mut(),
                d.mass.par_iter_mut(),
            ),
            d.vx.par_iter_mut(),
            d.vy.par_iter_mut(),
            d.vz.par_iter_mut(),
            (d.x.par_iter(), d.y.par_iter(), d.z.par_iter()),
            bc.par_iter(),
        )
            .into_par_iter()
            .for_each(|((p, rho, m), vx, vy, vz, (&x, &y, &z), o)| {
                if o[0] <= 0.0 {
                    return;
                }
                let mut pi = o[1];
                let zone = oc.zone([x, y, z][k], lo, hi);
                if zone == ZONE_OUTLET {
                    *vx = o[2];
                    *vy = o[3];
                    *vz = o[4];
                    if let Some(q) = p_out {
                        pi = q;
                    }
                }
                *p = pi;
                *rho = eos.density(pi);
                if zone == ZONE_INLET {
                    // a lattice particle at the density of the fluid it enters: its mass
                    // fills its lattice cell at that density, so the inflow's mass flux
                    // is rho_in u_in (a lattice particle of rest mass would bring a
                    // density its spacing does not have, and the fluid would keep the
                    // inlet's compression while draining through the outlet)
                    *m = *rho * cell;
                }
            });
    }
}
