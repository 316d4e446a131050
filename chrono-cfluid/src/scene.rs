//! Ready-made constraint-fluid scenes: the quasi-2D tank of
//! [`chrono_core::particles::lattice::SlabTank`] ([`TankScene`]: a dam break, still
//! water, a sloshing or incompressibility tank) in a system of its own.
//!
//! The geometry is the lattice module's, counted by [`Fit::Nearest`] with the walls on
//! the fluid's lattice ([`Anchor::Inner`]), as [`lattice_box`](crate::lattice_box) and
//! [`tank_markers`](crate::tank_markers) give it.

use chrono_core::descriptor::CcpSolver;
use chrono_core::error::{ChronoError, Result};
use chrono_core::item::ItemHandle;
use chrono_core::particles::lattice::{Anchor, Fit, SlabTank};
use chrono_core::{System, SystemSettings};

use crate::fluid::ConstraintFluid;
use crate::settings::CfluidSettings;

/// A quasi-2D tank of constraint fluid (a slab periodic in y): marker walls on the left,
/// the right and the floor, the block of fluid of a [`SlabTank`] against the left wall, in
/// a system (default [`SystemSettings`], so gravity is
/// [`GRAVITY`](chrono_core::math::GRAVITY)) with the fluid as its only item.
pub struct TankScene {
    /// The system.
    pub sys: System,
    /// The fluid's item index.
    pub id: ItemHandle,
    /// Slab thickness, m.
    pub ly: f64,
}

impl TankScene {
    /// Builds the scene of `tank` with the CCP solver `solver` (for example
    /// `chrono_ccp::Apgd`). `settings` brings the fluid model; its spacing and `h / dp`
    /// are set to the tank's, its domain to the tank with its wall layers,
    /// `[-t, length + t] x [0, ly] x [-t, top]` (`t = layers dp`), periodic in y.
    pub fn new(
        settings: CfluidSettings,
        tank: &SlabTank,
        solver: Box<dyn CcpSolver>,
    ) -> Result<Self> {
        let dp = tank.spacing;
        let ly = tank.thickness();
        let t = tank.layers() as f64 * dp;
        let settings = CfluidSettings {
            spacing: dp,
            h_over_dp: tank.h_over_dp,
            domain_lower: [-t, 0.0, -t],
            domain_upper: [tank.length + t, ly, tank.top],
            periodic: [false, true, false],
            ..settings
        };
        let set = tank.particles(Fit::Nearest, Anchor::Inner)?;
        let item = ConstraintFluid::new("water", settings, &set.fluid, &set.wall_positions())?;
        let mut sys = System::new(SystemSettings::default(), solver)?;
        let id = sys.add_item(Box::new(item));
        Ok(Self { sys, id, ly })
    }

    /// The fluid item.
    pub fn fluid(&self) -> Result<&ConstraintFluid> {
        self.sys.item::<ConstraintFluid>(self.id).ok_or_else(|| {
            ChronoError::invalid("scene.fluid", self.id, "the fluid item is missing")
        })
    }

    /// The fluid item, mutable (e.g. to recompute its densities).
    pub fn fluid_mut(&mut self) -> Result<&mut ConstraintFluid> {
        let id = self.id;
        self.sys
            .item_mut::<ConstraintFluid>(id)
            .ok_or_else(|| ChronoError::invalid("scene.fluid", id, "the fluid item is missing"))
    }
}
