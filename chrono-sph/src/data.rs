//! Particle storage: structure of arrays, one entry per particle (fluid and wall
//! markers together, sorted by cell every few steps).

use chrono_core::particles::permute;

/// The kind of a particle.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
pub enum Kind {
    /// A fluid particle (integrated).
    Fluid = 0,
    /// A wall marker (prescribed motion, pressure extrapolated from the fluid).
    Wall = 1,
}

/// `kind` code of fluid particles.
pub const FLUID: u8 = Kind::Fluid as u8;
/// `kind` code of wall markers.
pub const WALL: u8 = Kind::Wall as u8;

/// Time derivatives of one particle, written by the interaction pass: acceleration
/// (m/s^2), density rate (kg/m^3/s) and the XSPH velocity correction (m/s). Stored as
/// one 64-byte record per particle so the parallel pass writes one cache line.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Deriv {
    /// `dv/dt`, m/s^2 (gravity and body force included).
    pub acc: [f64; 3],
    /// `d rho / dt`, kg/m^3/s.
    pub drho: f64,
    /// XSPH correction `Delta v`, m/s.
    pub xsph: [f64; 3],
    /// Padding to 64 bytes.
    pub _pad: f64,
}

/// The particle arrays (structure of arrays). Index `i` is the current storage slot,
/// which changes when the arrays are re-sorted; `id[i]` is the stable particle id.
#[derive(Debug, Clone, Default)]
pub struct ParticleData {
    /// Position x, m.
    pub x: Vec<f64>,
    /// Position y, m.
    pub y: Vec<f64>,
    /// Position z, m.
    pub z: Vec<f64>,
    /// Velocity x, m/s (walls: the prescribed velocity).
    pub vx: Vec<f64>,
    /// Velocity y, m/s.
    pub vy: Vec<f64>,
    /// Velocity z, m/s.
    pub vz: Vec<f64>,
    /// Density, kg/m^3 (walls: extrapolated from the fluid).
    pub rho: Vec<f64>,
    /// Pressure, Pa (walls: extrapolated from the fluid).
    pub p: Vec<f64>,
    /// Mass, kg.
    pub mass: Vec<f64>,
    /// [`FLUID`] or [`WALL`].
    pub kind: Vec<u8>,
    /// Stable id (creation order).
    pub id: Vec<u32>,
    /// Wall group (to measure the force on one wall), 0 for fluid.
    pub group: Vec<u16>,
    /// Initial position of wall markers (their prescribed motion is relative to it).
    pub anchor: Vec<[f64; 3]>,
    /// Derivatives of the last evaluation.
    pub deriv: Vec<Deriv>,
    /// Wall markers moved by a rigid carrier ([`crate::carrier`]): the carrier index
    /// ([`NO_CARRIER`](crate::carrier::NO_CARRIER) otherwise); their `anchor` is then the
    /// body-frame offset.
    pub carrier: Vec<u32>,
    /// Carrier markers: the acceleration of the pressure extrapolation, m/s^2.
    pub(crate) wall_a: Vec<[f64; 3]>,
    /// Wall markers: the velocity used by the viscous term (no-slip extrapolation).
    pub(crate) wall_v: Vec<[f64; 3]>,
    /// Wall markers: unit normal of the wall surface they stand behind, pointing into the
    /// fluid (zero when unknown: [`NoSlip::Adami`](crate::NoSlip::Adami) extrapolation).
    pub(crate) wall_normal: Vec<[f64; 3]>,
    /// Wall markers: depth behind that wall surface, m (0 for fluid).
    pub(crate) wall_depth: Vec<f64>,
    /// Scratch of the Shepard filter.
    pub(crate) rho_half: Vec<f64>,
    scratch_f: Vec<f64>,
    scratch_u8: Vec<u8>,
    scratch_u32: Vec<u32>,
    scratch_u16: Vec<u16>,
    scratch_3: Vec<[f64; 3]>,
    scratch_d: Vec<Deriv>,
}

impl ParticleData {
    /// Number of particles.
    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// Whether there is no particle.
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    /// Appends one particle.
    pub(crate) fn push(&mut self, kind: Kind, pos: [f64; 3], rho: f64, mass: f64, group: u16) {
        self.push_with_normal(kind, pos, rho, mass, group, [0.0; 3], 0.0);
    }

    /// Appends one particle with a wall normal (pointing into the fluid) and the depth
    /// behind the wall surface, m (wall markers of a tank).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn push_with_normal(
        &mut self,
        kind: Kind,
        pos: [f64; 3],
        rho: f64,
        mass: f64,
        group: u16,
        normal: [f64; 3],
        depth: f64,
    ) {
        self.wall_normal.push(normal);
        self.wall_depth.push(depth);
        self.id.push(self.x.len() as u32);
        self.x.push(pos[0]);
        self.y.push(pos[1]);
        self.z.push(pos[2]);
        self.vx.push(0.0);
        self.vy.push(0.0);
        self.vz.push(0.0);
        self.rho.push(rho);
        self.p.push(0.0);
        self.mass.push(mass);
        self.kind.push(kind as u8);
        self.group.push(group);
        self.anchor.push(pos);
        self.deriv.push(Deriv::default());
        self.wall_v.push([0.0; 3]);
        self.rho_half.push(rho);
        self.carrier.push(crate::carrier::NO_CARRIER);
        self.wall_a.push([0.0; 3]);
    }

    /// Keeps the particles whose slot has `keep[i]` (in their order) and drops the rest
    /// (an open channel's outflow); returns the number dropped.
    pub(crate) fn retain(&mut self, keep: &[bool]) -> usize {
        fn compact<T: Copy>(v: &mut Vec<T>, keep: &[bool]) {
            let mut k = 0;
            for i in 0..v.len() {
                if keep[i] {
                    v[k] = v[i];
                    k += 1;
                }
            }
            v.truncate(k);
        }
        let n = self.len();
        for v in [
            &mut self.x,
            &mut self.y,
            &mut self.z,
            &mut self.vx,
            &mut self.vy,
            &mut self.vz,
            &mut self.rho,
            &mut self.p,
            &mut self.mass,
            &mut self.wall_depth,
            &mut self.rho_half,
        ] {
            compact(v, keep);
        }
        compact(&mut self.kind, keep);
        compact(&mut self.id, keep);
        compact(&mut self.carrier, keep);
        compact(&mut self.group, keep);
        for v in [
            &mut self.wall_a,
            &mut self.anchor,
            &mut self.wall_v,
            &mut self.wall_normal,
        ] {
            compact(v, keep);
        }
        compact(&mut self.deriv, keep);
        n - self.len()
    }

    /// Reorders every array by `order` (see [`chrono_core::particles::permute`]); no
    /// allocation once the scratch buffers have grown.
    pub(crate) fn permute(&mut self, order: &[u32]) {
        for v in [
            &mut self.x,
            &mut self.y,
            &mut self.z,
            &mut self.vx,
            &mut self.vy,
            &mut self.vz,
            &mut self.rho,
            &mut self.p,
            &mut self.mass,
            &mut self.wall_depth,
        ] {
            permute(order, v, &mut self.scratch_f);
        }
        permute(order, &mut self.kind, &mut self.scratch_u8);
        permute(order, &mut self.id, &mut self.scratch_u32);
        permute(order, &mut self.carrier, &mut self.scratch_u32);
        permute(order, &mut self.wall_a, &mut self.scratch_3);
        permute(order, &mut self.group, &mut self.scratch_u16);
        permute(order, &mut self.anchor, &mut self.scratch_3);
        permute(order, &mut self.wall_v, &mut self.scratch_3);
        permute(order, &mut self.wall_normal, &mut self.scratch_3);
        permute(order, &mut self.deriv, &mut self.scratch_d);
    }
}
