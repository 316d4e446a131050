//! Constraint-fluid validation cases (chrono-cfluid): the incompressibility test of the
//! seed ("Incompressibility Test" table), the dam break against Martin and Moyce (1952)
//! and a floating box against Archimedes.
//! See `docs/validation-cfluid.md`.

pub mod dam_break;
pub mod floating_box;
pub mod incompressibility;
pub mod sloshing;
pub mod still_water;
pub mod timestep;

use chrono_cfluid::{CfluidSettings, ConstraintFluid, lattice_box, tank_markers};
use chrono_core::descriptor::SolverSettings;
use chrono_core::{System, SystemSettings};

use crate::cases::sph::{slab_layers, wall_layers};

/// A quasi-2D tank of the cases (a slab periodic in y, `slab_layers` particles thick):
/// marker walls on the left, the right and the floor of `[0, tank_length] x [0, top]`,
/// a block of fluid `[0, column[0]] x [0, column[1]]` on the left, in a system with the
/// CCP solver `solver` (chrono-ccp name) at `tolerance` and `max_iterations`.
pub struct TankScene {
    /// The system with the fluid as its only item.
    pub sys: System,
    /// The fluid's item index.
    pub id: chrono_core::item::ItemHandle,
    /// Slab thickness, m.
    pub ly: f64,
}

impl TankScene {
    /// Build the scene; `settings` brings the spacing, `h_over_dp` and the fluid model, the
    /// domain (tank plus wall layers, periodic in y) is set here.
    pub fn new(
        settings: CfluidSettings,
        tank_length: f64,
        top: f64,
        column: [f64; 2],
        solver: &str,
        tolerance: f64,
        max_iterations: usize,
    ) -> anyhow::Result<Self> {
        let dp = settings.spacing;
        let layers = wall_layers(settings.h_over_dp);
        let ly = slab_layers(settings.h_over_dp) as f64 * dp;
        let t = layers as f64 * dp;
        let settings = CfluidSettings {
            domain_lower: [-t, 0.0, -t],
            domain_upper: [tank_length + t, ly, top],
            periodic: [false, true, false],
            ..settings
        };
        let fluid = lattice_box([0.0; 3], [column[0], ly, column[1]], dp)?;
        let walls = tank_markers(
            [0.0; 3],
            [tank_length, ly, top],
            dp,
            layers,
            [true, true, false, false, true, false],
        )?;
        let item = ConstraintFluid::new("water", settings, &fluid, &walls)?;
        let solver = chrono_ccp::by_name(
            solver,
            SolverSettings {
                tolerance,
                max_iterations,
                record_history: false,
            },
        )
        .map_err(|e| anyhow::anyhow!("parameter `solver`: {e}"))?;
        let mut sys = System::new(SystemSettings::default(), solver)?;
        let id = sys.add_item(Box::new(item));
        Ok(Self { sys, id, ly })
    }

    /// The fluid item.
    pub fn fluid(&self) -> anyhow::Result<&ConstraintFluid> {
        self.sys
            .item::<ConstraintFluid>(self.id)
            .ok_or_else(|| anyhow::anyhow!("the fluid item is missing"))
    }

    /// The fluid item, mutable (e.g. to recompute its densities).
    pub fn fluid_mut(&mut self) -> anyhow::Result<&mut ConstraintFluid> {
        self.sys
            .item_mut::<ConstraintFluid>(self.id)
            .ok_or_else(|| anyhow::anyhow!("the fluid item is missing"))
    }
}

/// Fluid particles outside the tank `[0, tank_length] x [0, ..)` by more than `dp / 2`.
pub fn left_tank(f: &ConstraintFluid, dp: f64, tank_length: f64) -> usize {
    (0..f.n_fluid())
        .filter(|&i| {
            let x = f.position(i);
            x[0] < -0.5 * dp || x[0] > tank_length + 0.5 * dp || x[2] < -0.5 * dp
        })
        .count()
}
