//! Particle set-ups on the cubic lattice: the one home of the initial particle
//! positions shared by the particle methods (chrono-sph, chrono-cfluid; later the body
//! markers of fluid–solid coupling and the material points of MPM).
//!
//! - [`Lattice`]: the cubic lattice of spacing `dp` whose cell centres are
//!   `origin + (i + 1/2) dp`, `i` integer; [`Lattice::fill`] fills a box with them (a fluid
//!   block or column), [`Lattice::tank`] gives the wall markers of a [`Tank`] with the
//!   face each marker belongs to, its inward normal and its depth behind the wall;
//! - [`Fit`]: how many cells a box holds when its extent is not a whole number of
//!   spacings;
//! - [`wall_layers`], [`slab_layers`]: marker layers covering the kernel support, and
//!   the thickness of a periodic slab (quasi-2D set-ups);
//! - [`SlabTank`]: the quasi-2D tank with a block of fluid on its left, as data
//!   ([`ParticleSet`]): the dam-break column ([`SlabTank::dam_break`]) and the sloshing
//!   tank ([`SlabTank::sloshing`]).
//!
//! Positions are in m; nothing here knows masses or densities (each fluid model sets its
//! own). The lattice of the walls must be the fluid's (same spacing, same alignment), so a
//! marker stands for the same volume `dp^3` as a fluid particle and the first marker layer
//! sits `dp` from the last fluid layer.
//!
//! ```
//! use chrono_core::particles::lattice::{Fit, Lattice, Tank};
//!
//! let dp = 0.1;
//! let lattice = Lattice::new([0.0; 3], dp).unwrap();
//! let water = lattice.fill([0.0; 3], [1.0, 0.3, 0.5], Fit::Nearest).unwrap();
//! assert_eq!(water.len(), 10 * 3 * 5);
//! // an open-top tank, periodic along y, two marker layers thick
//! let tank = Tank::new([0.0; 3], [1.0, 0.3, 1.0], 2, [true, true, false, false, true, false]);
//! let walls = lattice.tank(&tank, Fit::Nearest).unwrap();
//! assert_eq!(walls.len(), 3 * (14 * 12 - 10 * 10));
//! ```

use crate::error::{ChronoError, Result, check_positive};

/// How many lattice cells fit in an extent that is not a whole number of spacings.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Fit {
    /// The nearest whole count, `round(L / dp)`: the lattice volume closest to the box's
    /// (constraint fluids).
    #[default]
    Nearest,
    /// The cells that lie wholly inside, `floor(L / dp + 1e-6)` (the `1e-6` absorbs the
    /// round-off of an extent meant as a whole count): the box is never overfilled (SPH).
    Floor,
}

impl Fit {
    /// Cells along an extent `length` (m) at spacing `dp` (m); 0 for a non-positive extent.
    pub fn count(self, length: f64, dp: f64) -> usize {
        let cells = length / dp;
        match self {
            Fit::Nearest => cells.round().max(0.0) as usize,
            Fit::Floor => (cells + 1e-6).floor().max(0.0) as usize,
        }
    }
}

/// Which faces of a box: `[-x, +x, -y, +y, -z, +z]`. A tank's wall is on the faces that
/// are `true`; the others are open (a free top, or a periodic direction).
pub type Sides = [bool; 6];

/// The sides of an open-top tank periodic along y (a quasi-2D slab): walls at `-x`, `+x`
/// and the floor `-z`.
pub const SLAB_SIDES: Sides = [true, true, false, false, true, false];

/// Wall-marker layers covering the kernel support `2 h` at `h / dp = h_over_dp`:
/// `ceil(2 h / dp)` (at least 1).
pub fn wall_layers(h_over_dp: f64) -> usize {
    ((2.0 * h_over_dp) - 1e-9).ceil().max(1.0) as usize
}

/// Particles across a periodic slab at `h / dp = h_over_dp`: the smallest count with
/// `n dp >= 4 h (1 + 0.1)`, twice the neighbour-list radius with a 10 % Verlet skin, so
/// the minimum image is exact (at least 1).
pub fn slab_layers(h_over_dp: f64) -> usize {
    ((4.4 * h_over_dp) - 1e-9).ceil().max(1.0) as usize
}

fn check_box(field: &str, lower: [f64; 3], upper: [f64; 3]) -> Result<()> {
    for a in 0..3 {
        if !lower[a].is_finite() {
            return Err(ChronoError::invalid(
                format!("{field}.lower[{a}]"),
                lower[a],
                "must be finite",
            ));
        }
        if !(upper[a].is_finite() && upper[a] > lower[a]) {
            return Err(ChronoError::invalid(
                format!("{field}.upper[{a}]"),
                upper[a],
                format!("must be finite and > lower[{a}] = {}", lower[a]),
            ));
        }
    }
    Ok(())
}

/// A tank: the inner (fluid) box `[inner_lower, inner_upper]` (m) and `layers` lattice
/// layers of wall markers beyond each face marked in `sides`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tank {
    /// Lower corner of the inner box, m.
    pub inner_lower: [f64; 3],
    /// Upper corner of the inner box, m.
    pub inner_upper: [f64; 3],
    /// Marker layers behind each wall (see [`wall_layers`]).
    pub layers: usize,
    /// The faces that carry a wall.
    pub sides: Sides,
}

impl Tank {
    /// A tank of inner box `[inner_lower, inner_upper]` (m), `layers` thick on `sides`.
    pub fn new(inner_lower: [f64; 3], inner_upper: [f64; 3], layers: usize, sides: Sides) -> Self {
        Self {
            inner_lower,
            inner_upper,
            layers,
            sides,
        }
    }

    /// The outer box (the inner box grown by `layers dp` on the walled faces), m.
    pub fn outer(&self, dp: f64) -> ([f64; 3], [f64; 3]) {
        let t = self.layers as f64 * dp;
        let mut lo = self.inner_lower;
        let mut hi = self.inner_upper;
        for a in 0..3 {
            if self.sides[2 * a] {
                lo[a] -= t;
            }
            if self.sides[2 * a + 1] {
                hi[a] += t;
            }
        }
        (lo, hi)
    }
}

/// A wall marker of a [`Tank`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WallMarker {
    /// Position, m.
    pub position: [f64; 3],
    /// The face of the inner box it belongs to (`0..6`, in the order of [`Sides`]): the
    /// one it lies farthest beyond (ties to the lower index), so the force on one wall
    /// can be probed.
    pub face: usize,
    /// That face's inward unit normal.
    pub normal: [f64; 3],
    /// Its depth behind that face, m (`dp / 2` for the first layer).
    pub depth: f64,
}

/// The cubic lattice of spacing `dp` (m) with cell centres `origin + (i + 1/2) dp`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lattice {
    origin: [f64; 3],
    spacing: f64,
}

impl Lattice {
    /// The lattice through `origin` (m, a cell corner) at spacing `dp` (m, positive).
    pub fn new(origin: [f64; 3], dp: f64) -> Result<Self> {
        check_positive("lattice.spacing", dp)?;
        for (a, o) in origin.iter().enumerate() {
            if !o.is_finite() {
                return Err(ChronoError::invalid(
                    format!("lattice.origin[{a}]"),
                    o,
                    "must be finite",
                ));
            }
        }
        Ok(Self {
            origin,
            spacing: dp,
        })
    }

    /// The spacing `dp`, m.
    pub fn spacing(&self) -> f64 {
        self.spacing
    }

    /// The origin (a cell corner), m.
    pub fn origin(&self) -> [f64; 3] {
        self.origin
    }

    /// The centre `origin + (idx + 1/2) dp` of cell `idx`, m.
    pub fn point(&self, idx: [i64; 3]) -> [f64; 3] {
        std::array::from_fn(|a| self.origin[a] + (idx[a] as f64 + 0.5) * self.spacing)
    }

    /// Index of the cell whose lower corner is nearest `x` along each axis.
    fn corner_index(&self, x: [f64; 3]) -> [i64; 3] {
        std::array::from_fn(|a| ((x[a] - self.origin[a]) / self.spacing).round() as i64)
    }

    /// The cell centres filling the box `[lower, upper]` (m), `fit` cells along each axis
    /// from the lattice corner nearest `lower`, x fastest, then y, then z (a fluid block or
    /// column). Errors name the box corner that is not finite or not above `lower`.
    pub fn fill(&self, lower: [f64; 3], upper: [f64; 3], fit: Fit) -> Result<Vec<[f64; 3]>> {
        check_box("fill", lower, upper)?;
        let start = self.corner_index(lower);
        let n: [usize; 3] = std::array::from_fn(|a| fit.count(upper[a] - lower[a], self.spacing));
        let mut out = Vec::with_capacity(n[0] * n[1] * n[2]);
        for k in 0..n[2] as i64 {
            for j in 0..n[1] as i64 {
                for i in 0..n[0] as i64 {
                    out.push(self.point([start[0] + i, start[1] + j, start[2] + k]));
                }
            }
        }
        Ok(out)
    }

    /// The wall markers of `tank`, in lattice order (x fastest): the cells of the inner box
    /// (`fit` cells along each axis from the lattice corner nearest `inner_lower`) grown by
    /// `layers` on the walled faces, less those whose centre lies inside the inner box.
    /// Each gets the face it lies farthest beyond, that face's inward normal and its depth.
    /// Errors name the tank field that is invalid (`layers = 0`, an empty box).
    pub fn tank(&self, tank: &Tank, fit: Fit) -> Result<Vec<WallMarker>> {
        check_box("tank", tank.inner_lower, tank.inner_upper)?;
        if tank.layers == 0 {
            return Err(ChronoError::invalid(
                "tank.layers",
                tank.layers,
                "must be >= 1",
            ));
        }
        let (lo, hi) = (tank.inner_lower, tank.inner_upper);
        let start = self.corner_index(lo);
        let l = tank.layers as i64;
        let range = |a: usize| {
            let n = fit.count(hi[a] - lo[a], self.spacing) as i64;
            let first = start[a] - if tank.sides[2 * a] { l } else { 0 };
            let end = start[a] + n + if tank.sides[2 * a + 1] { l } else { 0 };
            first..end
        };
        let mut out = Vec::new();
        for k in range(2) {
            for j in range(1) {
                for i in range(0) {
                    let p = self.point([i, j, k]);
                    // how far beyond each face; the marker belongs to the largest
                    let over: [f64; 6] = std::array::from_fn(|f| {
                        let a = f / 2;
                        if f % 2 == 0 {
                            lo[a] - p[a]
                        } else {
                            p[a] - hi[a]
                        }
                    });
                    let mut face = 0;
                    for f in 1..6 {
                        if over[f] > over[face] {
                            face = f;
                        }
                    }
                    if over[face] <= 0.0 || !tank.sides[face] {
                        continue;
                    }
                    let mut normal = [0.0; 3];
                    normal[face / 2] = if face % 2 == 1 { -1.0 } else { 1.0 };
                    out.push(WallMarker {
                        position: p,
                        face,
                        normal,
                        depth: over[face],
                    });
                }
            }
        }
        Ok(out)
    }
}

/// An initial particle set: fluid particles and wall markers (the kinds), positions in m.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ParticleSet {
    /// Fluid particle positions, m.
    pub fluid: Vec<[f64; 3]>,
    /// Wall markers.
    pub walls: Vec<WallMarker>,
}

impl ParticleSet {
    /// The wall marker positions, m.
    pub fn wall_positions(&self) -> Vec<[f64; 3]> {
        self.walls.iter().map(|w| w.position).collect()
    }
}

/// Where the lattice of a [`SlabTank`]'s walls is anchored. The points are the same up to
/// round-off; each fluid model keeps the convention its validation cases were run with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Anchor {
    /// At the inner corner of the tank, the fluid block's lattice (constraint fluids).
    #[default]
    Inner,
    /// At the outer corner of the wall layers (SPH: every box on its own lattice).
    Outer,
}

/// A quasi-2D tank: a slab `slab_layers(h / dp) dp` thick along y (periodic), marker walls
/// on the left, the right and the floor of `[0, length] x [0, ly] x [0, top]` (open top),
/// and a block of fluid `[0, column[0]] x [0, ly] x [0, column[1]]` against the left wall.
/// The dam break is a narrow tall column in a long tank (Martin and Moyce 1952); the
/// sloshing tank is a full-width layer with headroom.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SlabTank {
    /// Lattice spacing `dp`, m.
    pub spacing: f64,
    /// Smoothing length over spacing `h / dp` (sets the wall layers and the slab).
    pub h_over_dp: f64,
    /// Inner tank length along x, m.
    pub length: f64,
    /// Height of the walls (top of the domain), m.
    pub top: f64,
    /// Fluid block `[width, height]`, m.
    pub column: [f64; 2],
}

impl SlabTank {
    /// The dam-break set-up: a column `[width, height]` (m) against the left wall of a
    /// tank `length` (m) long with walls `top` (m) high.
    pub fn dam_break(dp: f64, h_over_dp: f64, column: [f64; 2], length: f64, top: f64) -> Self {
        Self {
            spacing: dp,
            h_over_dp,
            length,
            top,
            column,
        }
    }

    /// The sloshing set-up: a tank `length` (m) long filled to `fill` (m), walls `top` (m)
    /// high.
    pub fn sloshing(dp: f64, h_over_dp: f64, length: f64, fill: f64, top: f64) -> Self {
        Self::dam_break(dp, h_over_dp, [length, fill], length, top)
    }

    /// The slab thickness `ly = slab_layers(h / dp) dp`, m.
    pub fn thickness(&self) -> f64 {
        slab_layers(self.h_over_dp) as f64 * self.spacing
    }

    /// Wall-marker layers, [`wall_layers`]`(h / dp)`.
    pub fn layers(&self) -> usize {
        wall_layers(self.h_over_dp)
    }

    /// The tank (inner box `[0, length] x [0, ly] x [0, top]`, [`SLAB_SIDES`]).
    pub fn tank(&self) -> Tank {
        Tank::new(
            [0.0; 3],
            [self.length, self.thickness(), self.top],
            self.layers(),
            SLAB_SIDES,
        )
    }

    /// The particles: the fluid block on the lattice through the origin, the walls on the
    /// lattice anchored by `anchor`, both counted by `fit`.
    pub fn particles(&self, fit: Fit, anchor: Anchor) -> Result<ParticleSet> {
        let dp = self.spacing;
        let ly = self.thickness();
        let fluid = Lattice::new([0.0; 3], dp)?.fill(
            [0.0; 3],
            [self.column[0], ly, self.column[1]],
            fit,
        )?;
        let tank = self.tank();
        let origin = match anchor {
            Anchor::Inner => tank.inner_lower,
            Anchor::Outer => tank.outer(dp).0,
        };
        let walls = Lattice::new(origin, dp)?.tank(&tank, fit)?;
        Ok(ParticleSet { fluid, walls })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layers_and_slab() {
        assert_eq!(slab_layers(1.3), 6);
        assert_eq!(slab_layers(1.5), 7);
        assert_eq!(wall_layers(1.3), 3);
        assert_eq!(wall_layers(1.5), 3);
    }

    #[test]
    fn fit_rules() {
        assert_eq!(Fit::Nearest.count(0.114, 0.005), 23);
        assert_eq!(Fit::Floor.count(0.114, 0.005), 22);
        assert_eq!(Fit::Floor.count(0.3, 0.1), 3);
        assert_eq!(Fit::Nearest.count(-1.0, 0.1), 0);
    }

    #[test]
    fn tank_faces_normals_depths() {
        let dp = 0.1;
        let lat = Lattice::new([0.0; 3], dp).unwrap();
        let tank = Tank::new([0.0; 3], [0.4, 0.2, 0.4], 2, SLAB_SIDES);
        let walls = lat.tank(&tank, Fit::Nearest).unwrap();
        // (4 + 4) x 6 outer minus 4 x 4 inner, times 2 along y
        assert_eq!(walls.len(), 2 * (8 * 6 - 16));
        for w in &walls {
            assert!(w.depth > 0.0 && w.depth < 2.0 * dp);
            let a = w.face / 2;
            assert_eq!(w.normal[a].abs(), 1.0);
            assert!(tank.sides[w.face]);
        }
        // the bottom corner below-left: equal overshoot, the lower face (-x) wins
        let c = walls
            .iter()
            .find(|w| w.position[0] < 0.0 && w.position[2] < 0.0)
            .unwrap();
        assert_eq!(c.face, 0);
    }

    #[test]
    fn errors_name_the_field() {
        let lat = Lattice::new([0.0; 3], 0.1).unwrap();
        let e = lat
            .fill([0.0; 3], [1.0, -1.0, 1.0], Fit::Nearest)
            .unwrap_err();
        assert!(e.to_string().contains("fill.upper[1]"));
        let e = lat
            .tank(&Tank::new([0.0; 3], [1.0; 3], 0, SLAB_SIDES), Fit::Nearest)
            .unwrap_err();
        assert!(e.to_string().contains("tank.layers"));
        assert!(Lattice::new([0.0; 3], 0.0).is_err());
    }

    #[test]
    fn slab_tank_set_up() {
        let s = SlabTank::dam_break(0.01, 1.3, [0.1, 0.2], 0.4, 0.3);
        let set = s.particles(Fit::Nearest, Anchor::Inner).unwrap();
        assert_eq!(set.fluid.len(), 10 * 6 * 20);
        let outer = s.particles(Fit::Nearest, Anchor::Outer).unwrap();
        assert_eq!(outer.walls.len(), set.walls.len());
        for (a, b) in outer.walls.iter().zip(&set.walls) {
            for k in 0..3 {
                assert!((a.position[k] - b.position[k]).abs() < 1e-12);
            }
            // corner markers lie equally far beyond two faces: which one wins the tie
            // depends on the round-off of the anchoring, their depth does not
            assert!(a.face == b.face || (a.depth - b.depth).abs() < 1e-12);
        }
    }
}
