//! The scene of `granular-repose` (see `repose.rs` for the reference and the checks): the
//! library's heap slot ([`HeapSlot`]) on a system with the NSC solver the `solver`
//! parameter names, the case's parameters mapped onto it.

use std::ops::Deref;

use chrono_core::granular::{Heap, HeapSlot};
use chrono_core::system::ContactMethod;
use chrono_core::{ContactFriction, ContactMaterial, SystemSettings};

use super::repose::ReposeParams;
use super::{grain_frames, make_system, record_grains};
use crate::case::RunContext;

/// One heap and what it cost.
pub(super) struct HeapRun {
    pub heap: Heap,
    pub steps: u64,
    pub wall_s: f64,
}

impl Deref for HeapRun {
    type Target = Heap;
    fn deref(&self) -> &Heap {
        &self.heap
    }
}

/// The NSC solver named by the `solver` parameter.
pub(super) fn solver(
    name: &str,
    tolerance: f64,
    max_iterations: usize,
) -> anyhow::Result<Box<dyn chrono_ccp::CcpSolver>> {
    let settings = chrono_ccp::SolverSettings {
        tolerance,
        max_iterations,
        record_history: false,
    };
    Ok(match name {
        "apgd" => Box::new(chrono_ccp::Apgd::new(settings)),
        "bb" => Box::new(chrono_ccp::BarzilaiBorwein::new(settings)),
        "psor" => Box::new(chrono_ccp::Psor::new(settings)),
        other => anyhow::bail!("parameter `solver` must be `apgd`, `bb` or `psor`, got `{other}`"),
    })
}

/// Settle a bed behind the gates, open them and return the heap left on the plate after
/// `t_discharge`, for one method, rolling friction `mu_r` and packing `seed`.
pub(super) fn heap(
    p: &ReposeParams,
    method: ContactMethod,
    mu_r: f64,
    seed: u64,
    ctx: &RunContext,
    progress: (usize, usize),
) -> anyhow::Result<HeapRun> {
    let start = std::time::Instant::now();
    let d = p.grain_diameter;
    let settings = SystemSettings {
        envelope: 0.05 * d,
        rolling_model: p.rolling_model,
        ..SystemSettings::default()
    };
    let mut sys = make_system(method, settings, p.tolerance, p.max_iterations)?;
    sys.set_solver(solver(&p.solver, p.tolerance, p.max_iterations)?);
    let mat = ContactMaterial::smc(p.young, 0.3, p.restitution, p.mu).with_rolling_friction(mu_r);
    let slot = HeapSlot {
        plate_width: p.plate_width,
        thickness: p.thickness,
        bed_height: p.bed_height,
        density: p.density,
        // Walls, plate and gates impose their own friction on the grains (Zhou et al.'s
        // mu_pw).
        wall_friction: ContactFriction {
            friction: p.wall_mu.unwrap_or(p.mu),
            rolling_friction: p.wall_rolling_friction.unwrap_or(mu_r),
            spinning_friction: 0.0,
        },
        rough_base: p.rough_base,
        seed,
        h: p.h,
        t_settle: p.t_settle,
        t_discharge: p.t_discharge,
        ..HeapSlot::new(d, mat)
    };
    let mut scene = slot.build(&mut sys).map_err(|e| {
        anyhow::anyhow!("granular-repose: {e} (the grain count follows bed_height)")
    })?;
    let (h, n) = (scene.h(), scene.total_steps());
    let mut vtk = grain_frames(ctx, (0.02 / h).round() as u64)?;
    let heap = scene
        .run(&mut sys, |sys, i| {
            record_grains(&mut vtk, i, sys)?;
            let (j, m) = progress;
            ctx.progress((j as f64 + i as f64 / n as f64) / m as f64);
            Ok::<(), anyhow::Error>(())
        })
        .map_err(|e| anyhow::anyhow!("granular-repose (mu = {}, mu_r = {mu_r}): {e}", p.mu))?;
    vtk.finish()?;
    Ok(HeapRun {
        heap,
        steps: n,
        wall_s: start.elapsed().as_secs_f64(),
    })
}
