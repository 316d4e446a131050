//! Ready-made SPH scenes on the quasi-2D tank of
//! [`chrono_core::particles::lattice::SlabTank`]: the dam break and the sloshing tank.
//!
//! The geometry (fluid block, wall markers, slab thickness) is the lattice module's; this
//! module adds what is SPH's: the domain, the periodic slab, the hydrostatic initial
//! density below the block's top and, for sloshing, the tank's motion. Boxes are counted
//! by [`Fit::Floor`] (never overfilled) and the walls anchored at their outer corner
//! ([`Anchor::Outer`]), as [`SphBuilder::add_fluid_box`] and [`SphBuilder::add_tank`] do.

use chrono_core::particles::lattice::{Anchor, Fit, SlabTank};

use crate::builder::SphBuilder;
use crate::error::Result;
use crate::motion::WallMotion;
use crate::settings::SphSettings;
use crate::system::SphSystem;

/// The builder of a slab tank: `settings` with the domain `[lower, upper]` (m) and the
/// periodic y set, the fluid block (hydrostatic density below its top) and the walls
/// (groups by face, see [`SphBuilder::add_wall_markers`]).
fn slab_builder(
    settings: SphSettings,
    tank: &SlabTank,
    lower: [f64; 3],
    upper: [f64; 3],
    motion: WallMotion,
) -> Result<SphSystem> {
    let settings = SphSettings {
        spacing: tank.spacing,
        h_over_dp: tank.h_over_dp,
        domain_lower: lower,
        domain_upper: upper,
        periodic: [false, true, false],
        ..settings
    };
    let mut b = SphBuilder::new(settings)?.motion(motion)?;
    let set = tank.particles(Fit::Floor, Anchor::Outer)?;
    b.add_particles(&set, Some(tank.column[1]));
    b.build()
}

/// The block of `tank` released at rest in its fixed tank: a dam break (Martin and Moyce
/// 1952) when the column is narrower than the tank, still water (hydrostatics) when it
/// fills the tank's width. `settings` brings the fluid model (sound speed, kernel,
/// viscosities, no-slip...); the spacing and `h / dp` are the tank's and the domain is the
/// tank's inner box `[0, length] x [0, ly] x [0, top]`, periodic along y.
pub fn slab_tank(settings: SphSettings, tank: &SlabTank) -> Result<SphSystem> {
    let upper = [tank.length, tank.thickness(), tank.top];
    slab_builder(settings, tank, [0.0; 3], upper, WallMotion::Fixed)
}

/// A sloshing tank: the tank of `tank` moved along x as
/// `x(t) = amplitude sin(omega t)` (m, rad/s; the amplitude ramped up over `ramp` s, see
/// [`WallMotion::Sinusoid`]). The domain is grown by the amplitude plus the wall layers
/// and two spacings, so the walls stay inside it.
pub fn sloshing(
    settings: SphSettings,
    tank: &SlabTank,
    amplitude: f64,
    omega: f64,
    ramp: f64,
) -> Result<SphSystem> {
    let dp = tank.spacing;
    let margin = amplitude + (tank.layers() as f64 + 2.0) * dp;
    let lower = [-margin, 0.0, -margin];
    let upper = [tank.length + margin, tank.thickness(), tank.top];
    let motion = WallMotion::Sinusoid {
        amplitude: [amplitude, 0.0, 0.0],
        omega,
        ramp,
    };
    slab_builder(settings, tank, lower, upper, motion)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dam_break_scene_matches_the_builder() {
        let dp = 0.02;
        let tank = SlabTank::dam_break(dp, 1.3, [0.1, 0.2], 0.4, 0.25);
        let settings = SphSettings {
            sound_speed: 20.0,
            ..SphSettings::default()
        };
        let sys = slab_tank(settings.clone(), &tank).unwrap();
        let ly = tank.thickness();
        let mut b = SphBuilder::new(SphSettings {
            spacing: dp,
            h_over_dp: 1.3,
            domain_lower: [0.0; 3],
            domain_upper: [0.4, ly, 0.25],
            periodic: [false, true, false],
            ..settings
        })
        .unwrap();
        b.add_fluid_box([0.0; 3], [0.1, ly, 0.2], Some(0.2))
            .unwrap();
        b.add_tank(
            [0.0; 3],
            [0.4, ly, 0.25],
            tank.layers(),
            tank.tank().sides,
            0,
        )
        .unwrap();
        let by_hand = b.build().unwrap();
        assert_eq!(sys.data().len(), by_hand.data().len());
        assert_eq!(sys.data().x, by_hand.data().x);
        assert_eq!(sys.data().z, by_hand.data().z);
        assert_eq!(sys.data().group, by_hand.data().group);
    }
}
