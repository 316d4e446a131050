//! The particle records that travel between ranks: a migrating particle's (or a new
//! ghost's) whole state, and the fields each ghost refresh carries.

use crate::data::{Deriv, ParticleData};

/// `f64`s of a whole particle state (migration and new ghosts): position, velocity,
/// density, pressure, mass, kind, id, group, anchor, carrier, the carrier acceleration,
/// the wall's no-slip velocity, normal and depth. Integers travel as `f64` (exact below
/// 2^53).
pub(crate) const MIGRATE_LEN: usize = 26;

/// What a ghost refresh carries (see the [module docs](super)).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Refresh {
    /// Position and velocity, after the drift.
    Kinematic,
    /// Density, after the density increment.
    Density,
    /// Density, pressure, mass (a wall marker's follows its extrapolated density) and
    /// the wall's no-slip velocity, after the wall extrapolation.
    Wall,
}

/// `f64`s per ghost of each [`Refresh`].
pub(crate) const GHOST_FIELDS: [usize; 3] = [6, 1, 6];

impl Refresh {
    pub(crate) fn len(self) -> usize {
        GHOST_FIELDS[self as usize]
    }

    /// Appends slot `i`'s fields to `buf`.
    #[inline]
    pub(crate) fn pack(self, d: &ParticleData, i: usize, buf: &mut Vec<f64>) {
        match self {
            Refresh::Kinematic => {
                buf.extend_from_slice(&[d.x[i], d.y[i], d.z[i], d.vx[i], d.vy[i], d.vz[i]])
            }
            Refresh::Density => buf.push(d.rho[i]),
            Refresh::Wall => {
                let v = d.wall_v[i];
                buf.extend_from_slice(&[d.rho[i], d.p[i], d.mass[i], v[0], v[1], v[2]]);
            }
        }
    }

    /// Sets slot `i`'s fields from `r` (`self.len()` values).
    #[inline]
    pub(crate) fn unpack(self, d: &mut ParticleData, i: usize, r: &[f64]) {
        match self {
            Refresh::Kinematic => {
                d.x[i] = r[0];
                d.y[i] = r[1];
                d.z[i] = r[2];
                d.vx[i] = r[3];
                d.vy[i] = r[4];
                d.vz[i] = r[5];
            }
            Refresh::Density => d.rho[i] = r[0],
            Refresh::Wall => {
                d.rho[i] = r[0];
                d.p[i] = r[1];
                d.mass[i] = r[2];
                d.wall_v[i] = [r[3], r[4], r[5]];
            }
        }
    }
}

/// Appends slot `i`'s whole state ([`MIGRATE_LEN`] values) to `buf`.
pub(crate) fn pack_state(d: &ParticleData, i: usize, buf: &mut Vec<f64>) {
    let (a, wa, wv, n) = (d.anchor[i], d.wall_a[i], d.wall_v[i], d.wall_normal[i]);
    buf.extend_from_slice(&[
        d.x[i],
        d.y[i],
        d.z[i],
        d.vx[i],
        d.vy[i],
        d.vz[i],
        d.rho[i],
        d.p[i],
        d.mass[i],
        d.kind[i] as f64,
        d.id[i] as f64,
        d.group[i] as f64,
        a[0],
        a[1],
        a[2],
        d.carrier[i] as f64,
        wa[0],
        wa[1],
        wa[2],
        wv[0],
        wv[1],
        wv[2],
        n[0],
        n[1],
        n[2],
        d.wall_depth[i],
    ]);
}

/// Appends a particle with the state `r` ([`MIGRATE_LEN`] values, as [`pack_state`]).
pub(crate) fn push_state(d: &mut ParticleData, r: &[f64]) {
    d.x.push(r[0]);
    d.y.push(r[1]);
    d.z.push(r[2]);
    d.vx.push(r[3]);
    d.vy.push(r[4]);
    d.vz.push(r[5]);
    d.rho.push(r[6]);
    d.p.push(r[7]);
    d.mass.push(r[8]);
    d.kind.push(r[9] as u8);
    d.id.push(r[10] as u32);
    d.group.push(r[11] as u16);
    d.anchor.push([r[12], r[13], r[14]]);
    d.carrier.push(r[15] as u32);
    d.wall_a.push([r[16], r[17], r[18]]);
    d.wall_v.push([r[19], r[20], r[21]]);
    d.wall_normal.push([r[22], r[23], r[24]]);
    d.wall_depth.push(r[25]);
    d.deriv.push(Deriv::default());
    d.rho_half.push(r[6]);
}

/// Keeps the slots with `keep[i]`, in order (no allocation).
pub(crate) fn compact<T: Copy>(v: &mut Vec<T>, keep: &[bool]) {
    let mut w = 0;
    for i in 0..v.len() {
        if keep[i] {
            v[w] = v[i];
            w += 1;
        }
    }
    v.truncate(w);
}

/// [`compact`] of every array of `d`.
pub(crate) fn compact_data(d: &mut ParticleData, keep: &[bool]) {
    for v in [
        &mut d.x,
        &mut d.y,
        &mut d.z,
        &mut d.vx,
        &mut d.vy,
        &mut d.vz,
        &mut d.rho,
        &mut d.p,
        &mut d.mass,
        &mut d.wall_depth,
        &mut d.rho_half,
    ] {
        compact(v, keep);
    }
    compact(&mut d.kind, keep);
    compact(&mut d.id, keep);
    compact(&mut d.group, keep);
    compact(&mut d.anchor, keep);
    compact(&mut d.carrier, keep);
    compact(&mut d.wall_a, keep);
    compact(&mut d.wall_v, keep);
    compact(&mut d.wall_normal, keep);
    compact(&mut d.deriv, keep);
}
