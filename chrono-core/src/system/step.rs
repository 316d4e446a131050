//! The NSC time step (Anitescu–Tasora, seed "Complementarity Approach: The Math").

use nalgebra::Vector3;
use rayon::prelude::*;

use super::{BODY_CHUNK, PARALLEL_MIN_BODIES, StepReport, System};
use crate::body::{BodyMotion, RigidBody};
use crate::contact::nsc::{self, NscRowSettings};
use crate::error::{ChronoError, Result};
use crate::item::StepContext;

impl System {
    /// The context the items see in a step of size `h` from the current state.
    pub(crate) fn step_context(&self, h: f64) -> StepContext {
        StepContext {
            h,
            time: self.time,
            step: self.step_count,
            gravity: self.settings.gravity,
        }
    }

    /// This step's variables: a block per dynamic body (fixed and kinematic bodies have
    /// none), then the items' blocks (each item's [`begin_step`](crate::item::PhysicsItem::begin_step) first).
    pub(crate) fn add_step_variables(&mut self, ctx: &StepContext) -> Result<()> {
        for item in &mut self.items {
            item.begin_step(ctx)?;
        }
        self.vars.clear();
        for b in &mut self.bodies {
            b.block = match b.motion {
                BodyMotion::Dynamic => Some(self.vars.add_oriented(b.mass_operator()?, b.rotation)),
                _ => None,
            };
        }
        for item in &mut self.items {
            item.add_variables(&mut self.vars);
        }
        Ok(())
    }

    /// Copy the solved velocities `self.v` into the dynamic bodies and advance every
    /// non-fixed body's pose by `h` (in parallel for many bodies).
    pub(crate) fn update_bodies(&mut self, h: f64) {
        self.poses_fresh = false;
        let (vars, v) = (&self.vars, &self.v);
        let one = |b: &mut RigidBody| {
            if let Some(blk) = b.block {
                let v = &v[vars.range(blk)];
                b.linear_velocity = Vector3::new(v[0], v[1], v[2]);
                b.angular_velocity = Vector3::new(v[3], v[4], v[5]);
            }
            if b.motion != BodyMotion::Fixed {
                b.integrate_pose(h);
            }
        };
        if self.bodies.len() >= PARALLEL_MIN_BODIES {
            (self.bodies.par_iter_mut())
                .with_min_len(BODY_CHUNK)
                .for_each(one);
        } else {
            self.bodies.iter_mut().for_each(one);
        }
    }

    /// Advance by one step of size `h` (s):
    ///
    /// 1. collide at `q(l)` (contacts within the envelope), bodies with bodies and the
    ///    items' collision proxies with bodies;
    /// 2. assemble `k = M v(l) + h f(t, q, v)` and the rows: joints (`D'v + C/h = 0`),
    ///    contacts (friction cones, `b_n = max(Phi/h, -v_rec)`), the items' rows;
    /// 3. solve the CCP for the impulses `g`, warm-started from the last step;
    /// 4. `v(l+1) = M^-1 (k + D g)`, then `q(l+1) = q(l) + h L(q) v(l+1)`
    ///    (quaternions by the exponential map).
    ///
    /// Errors: `h` not finite and > 0; a non-finite state after the step (the error names the
    /// body or item and the step, and the state is left as it was computed).
    pub fn step(&mut self, h: f64) -> Result<StepReport> {
        crate::parallel::on_worker(|| self.step_here(h))
    }

    /// [`System::step`] on the calling thread (see [`crate::parallel::on_worker`]).
    fn step_here(&mut self, h: f64) -> Result<StepReport> {
        if self.settings.contact_method == super::ContactMethod::Smc {
            return self.step_smc(h);
        }
        if !(h.is_finite() && h > 0.0) {
            return Err(ChronoError::invalid(
                "h",
                h,
                "the step size must be finite and > 0",
            ));
        }
        let ctx = self.step_context(h);

        self.add_step_variables(&ctx)?;

        // Momentum k = M v + h f.
        let ndof = self.vars.ndof();
        self.k.clear();
        self.k.resize(ndof, 0.0);
        self.gather_loads(&ctx)?;
        free_momenta(
            &self.bodies,
            self.loads.as_slice(),
            &self.settings.gravity,
            h,
            &mut self.momentum,
        );
        for (i, (b, k)) in self.bodies.iter().zip(&self.momentum).enumerate() {
            if let Some(blk) = b.block {
                let r = self.vars.range(blk);
                self.k[r].copy_from_slice(k);
                if k.iter().any(|x| !x.is_finite()) {
                    return Err(ChronoError::NonFinite {
                        item: format!("body {i} (\"{}\")", b.name),
                        step: self.step_count,
                        time: self.time,
                        what: "momentum M v + h f (velocity or applied force too large)".into(),
                    });
                }
            }
        }
        for item in &self.items {
            item.load_momentum(&ctx, &self.vars, &mut self.k);
        }

        // Collision at q(l). NSC steps move grains too far for a skin to pay.
        self.collision.set_sphere_skin(0.0)?;
        self.collision_state();
        self.points.clear();
        self.collision
            .detect(&self.poses, &self.active, &mut self.points)?;
        self.apply_contact_friction();
        self.proxy_points.clear();
        for (i, item) in self.items.iter().enumerate() {
            self.proxies.clear();
            item.collision_proxies(&mut self.proxies);
            self.collision
                .detect_proxies(i as u32, &self.proxies, &mut self.proxy_points)?;
        }

        // Rows.
        self.rows.clear();
        for j in &mut self.joints {
            j.add_rows(&self.bodies, h, &mut self.rows);
        }
        self.contacts.clear();
        let row_settings = NscRowSettings {
            h,
            max_recovery_speed: self.settings.max_recovery_speed,
            rolling_model: self.settings.rolling_model,
        };
        nsc::add_contact_rows(
            &self.points,
            &self.bodies,
            row_settings,
            &mut self.rows,
            &mut self.triplet,
            &mut self.contacts,
        )?;
        self.proxy_contacts.clear();
        nsc::add_proxy_contact_rows(
            &self.proxy_points,
            &self.bodies,
            &self.items,
            row_settings,
            &mut self.rows,
            &mut self.triplet,
            &mut self.proxy_contacts,
        )?;
        for item in &mut self.items {
            item.add_constraints(&ctx, &self.vars, &mut self.rows)?;
            item.add_body_constraints(&ctx, &self.bodies, &self.vars, &mut self.rows)?;
        }

        // Assemble and solve.
        self.problem
            .assemble_taking(&self.vars, &mut self.rows, &self.k)?;
        let m = self.problem.n_rows();
        self.gamma.clear();
        self.gamma.resize(m, 0.0);
        if self.settings.warm_start {
            nsc::warm_start(
                &self.contacts,
                &mut self.cache,
                &self.problem,
                &mut self.gamma,
            );
            nsc::warm_start_proxies(
                &self.proxy_contacts,
                &mut self.cache,
                &self.problem,
                &mut self.gamma,
            );
            for j in &self.joints {
                if j.impulses.len() == j.row_ids.len() {
                    for (id, g) in j.row_ids.iter().zip(&j.impulses) {
                        self.gamma[self.problem.row_index(*id)] = *g;
                    }
                }
            }
            for item in &self.items {
                item.warm_start(&self.problem, &mut self.gamma);
            }
        }
        let mut solve = self.solver.solve(&self.problem, &mut self.gamma);
        let mut friction_passes = 0;
        if let super::FrictionLaw::Coulomb { passes } = self.settings.friction_law {
            (solve, friction_passes) = self.coulomb_passes(passes, solve);
        }
        if let Some(i) = self.gamma.iter().position(|g| !g.is_finite()) {
            return Err(ChronoError::NonFinite {
                item: format!("CCP row {i}"),
                step: self.step_count,
                time: self.time,
                what: format!("impulse from solver `{}`", self.solver.name()),
            });
        }

        // v(l+1) and q(l+1).
        self.v.clear();
        self.v.resize(ndof, 0.0);
        self.problem.velocities(&self.gamma, &mut self.v);
        self.update_bodies(h);
        for item in &mut self.items {
            item.update(&ctx, &self.vars, &self.v, &self.problem, &self.gamma)?;
        }

        // Caches for the next step.
        nsc::store(&self.contacts, &self.problem, &self.gamma, &mut self.cache);
        nsc::store_proxies(
            &self.proxy_contacts,
            &self.problem,
            &self.gamma,
            &mut self.cache,
        );
        for j in &mut self.joints {
            j.impulses.clear();
            for id in &j.row_ids {
                j.impulses.push(self.gamma[self.problem.row_index(*id)]);
            }
        }

        self.check_state()?;
        self.time += h;
        self.step_count += 1;
        Ok(StepReport {
            contacts: self.contacts.len() + self.proxy_contacts.len(),
            rows: m,
            solve,
            friction_passes,
        })
    }
}

/// `k = M v + h f` of every body with a variable block ([`RigidBody::free_momentum`](crate::RigidBody))
/// with the loads `loads` (per body), into `out` (zeros for the others); in parallel for
/// many bodies (each body on its own: deterministic).
pub(crate) fn free_momenta(
    bodies: &[RigidBody],
    loads: &[[Vector3<f64>; 2]],
    gravity: &Vector3<f64>,
    h: f64,
    out: &mut Vec<[f64; 6]>,
) {
    let n = bodies.len();
    out.clear();
    out.resize(n, [0.0; 6]);
    let one = |(b, (load, k)): (&RigidBody, (&[Vector3<f64>; 2], &mut [f64; 6]))| {
        if b.block.is_some() {
            b.free_momentum(h, gravity, load, k);
        }
    };
    let loads = &loads[..n];
    if n >= PARALLEL_MIN_BODIES {
        (bodies.par_iter())
            .zip(loads.par_iter().zip(out.par_iter_mut()))
            .with_min_len(BODY_CHUNK)
            .for_each(one);
    } else {
        (bodies.iter())
            .zip(loads.iter().zip(out.iter_mut()))
            .for_each(one);
    }
}
