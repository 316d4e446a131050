//! Grid to particle ([`MpmBody::g2p`]) in passes: the markers' velocity, affine matrix
//! and velocity-gradient increment; the F-bar volume averaging of the increments (when
//! [`MpmSettings::f_bar`]); the deformation gradient with its return mapping (then the
//! plastic variant's averaging); the position.

use super::*;
use crate::fbar;
use crate::pressure::StrainFrom;

impl MpmBody {
    /// Grid to particle: velocity, affine matrix, deformation gradient (with the F-bar
    /// average when set, then the return mapping) and position.
    pub(crate) fn g2p(&mut self, dt: f64) -> Result<()> {
        let mut t = Instant::now();
        self.g2p_velocity(dt);
        self.status.clear();
        self.status.resize(self.markers.len(), 0);
        lap(&mut t, &mut self.timings.g2p);
        if let Some(rows) = self.pressure.as_mut().filter(|_| dt > 0.0) {
            // the split: the pressure rows correct the markers' velocities (and the step's
            // velocity gradient) before F_E is updated and the markers move
            rows.solve(
                &mut self.markers,
                &mut self.rigid,
                dt,
                self.steps,
                self.time,
            )?;
            t = Instant::now();
            let from = rows.settings().strain_from;
            if from == StrainFrom::GridPlusRows {
                rows.add_velocity_gradient(dt, &mut self.df);
            } else {
                self.strain_from_final_velocities(dt);
            }
            if let Some(rows) = self.pressure.as_mut() {
                rows.match_volume(&self.markers, &mut self.df);
                lap(&mut t, &mut rows.timing[2]);
            }
        }
        let mode = self.settings.f_bar;
        if matches!(mode, FBar::Increment | FBar::Total) {
            self.f_bar_increments(mode);
        }
        if mode == FBar::PlasticIncrement {
            let mk = &self.markers;
            self.vol_dj.clear();
            self.vol_dj
                .extend((0..mk.len()).map(|p| [mk.fe[p].determinant(), mk.fp[p].determinant()]));
        }
        self.project(dt);
        if mode == FBar::PlasticIncrement {
            self.f_bar_plastic();
        }
        lap(&mut t, &mut self.timings.constitutive);
        self.advect(dt);
        let r = self.check_status();
        lap(&mut t, &mut self.timings.advect);
        r
    }

    /// `v_p = sum_i w_ip v_i`, `C_p = 4/dx^2 sum_i w_ip v_i (x_i - x_p)^T` and the increment
    /// `dF_p = I + dt sum_i v_i grad w_ip^T` (in `self.df`); the positions stay (the F-bar
    /// pass reads the stencils of the step's start).
    pub(crate) fn g2p_velocity(&mut self, dt: f64) {
        let spec = self.spec;
        let nb = spec.blocks();
        let (origin, dx) = (spec.origin, spec.dx);
        let dinv = apic_d_inverse(dx);
        let grid = &self.grid;
        let flip = self.flip;
        let mk = &mut self.markers;
        self.df.clear();
        self.df.resize(mk.len(), Matrix3::zeros());
        mk.x.par_iter()
            .zip(mk.v.par_iter_mut())
            .zip(mk.c.par_iter_mut())
            .zip(self.df.par_iter_mut())
            .with_min_len(MARKERS_PER_TASK)
            .for_each(|(((x, v), c), df)| {
                let st = Stencil::new((*x).into(), origin, dx);
                let mut vp = Vector3::zeros();
                let mut bp = Matrix3::zeros();
                let mut grad_v = Matrix3::zeros();
                let mut v_old = Vector3::zeros();
                fbar::for_stencil_nodes(grid, nb, &st, |o, node| {
                    let vi = Vector3::from(grid.mom[node]);
                    let w = st.weight(o);
                    let r = Vector3::from(st.offset(o, dx));
                    let gw = Vector3::from(st.grad(o));
                    vp += vi * w;
                    bp += (vi * w) * r.transpose();
                    grad_v += vi * gw.transpose();
                    if flip > 0.0 && grid.mass[node] > 0.0 {
                        v_old += Vector3::from(grid.mom0[node]) * (w / grid.mass[node]);
                    }
                });
                *v = if flip > 0.0 {
                    vp + (*v - v_old) * flip
                } else {
                    vp
                };
                *c = bp * dinv;
                *df = Matrix3::identity() + grad_v * dt;
            });
    }

    /// The split's increment `dF_p = I + dt sum_i v_i grad w_ip'` from the step's *final*
    /// velocities ([`StrainFrom::FinalGrid`]): the markers' velocities after the rows,
    /// rasterized by mass (`v_i = sum_p w_ip m_p v_p / m_i`, no affine part, so markers at
    /// rest give a grid at rest), under the walls' conditions (no gravity, the rigid
    /// bodies' nodes left as the markers carry them). The grid's gradient is the adjoint of
    /// the grid's stress divergence, as in plain MPM; the markers have not moved yet, so
    /// the stencils and the nodes' masses are those of this step's P2G.
    pub(crate) fn strain_from_final_velocities(&mut self, dt: f64) {
        let mk = &self.markers;
        let sorted = &self.grid.sorted;
        self.scratch
            .par_iter_mut()
            .with_min_len(MARKERS_PER_TASK)
            .enumerate()
            .for_each(|(s, d)| {
                let p = sorted[s].1 as usize;
                d.mv = (mk.v[p] * d.m).into();
                d.mc = [[0.0; 3]; 3];
            });
        let (nb, dx, origin) = (self.spec.blocks(), self.spec.dx, self.spec.origin);
        let mut mom = std::mem::take(&mut self.grid.mom);
        transfer_gather(&self.grid, &self.scratch, nb, dx, &mut mom);
        self.grid.mom = mom;
        self.grid_velocities(false);
        let grid = &self.grid;
        self.markers
            .x
            .par_iter()
            .zip(self.df.par_iter_mut())
            .with_min_len(MARKERS_PER_TASK)
            .for_each(|(x, df)| {
                let st = Stencil::new((*x).into(), origin, dx);
                let mut grad_v = Matrix3::zeros();
                fbar::for_stencil_nodes(grid, nb, &st, |o, node| {
                    grad_v += Vector3::from(grid.mom[node]) * Vector3::from(st.grad(o)).transpose();
                });
                *df = Matrix3::identity() + grad_v * dt;
            });
    }

    /// F-bar ([`crate::fbar`]): each increment `dF_p` scaled by `(dJbar_p / dJ_p)^(1/3)`,
    /// `dJbar_p` the volume-weighted stencil average of the increments `dJ = det dF`
    /// ([`FBar::Increment`]), or by `(Jbar_p / J_p)^(1/3)` with the average of the total
    /// `J = det(dF F_E F_P)` ([`FBar::Total`]). A non-positive `J`, `dJ` or average marks
    /// the marker `BAD_VOLUME`.
    pub(crate) fn f_bar_increments(&mut self, mode: FBar) {
        let mk = &self.markers;
        let n = mk.len();
        self.vol_dj.clear();
        self.vol_dj.resize(n, [0.0; 2]);
        self.vol_dj
            .par_iter_mut()
            .zip(self.df.par_iter())
            .enumerate()
            .with_min_len(MARKERS_PER_TASK)
            .for_each(|(p, (vd, df))| {
                let j = mk.fe[p].determinant() * mk.fp[p].determinant();
                let v0 = mk.volume0[p];
                *vd = match mode {
                    FBar::Total => [v0, v0 * j * df.determinant()],
                    _ => [v0 * j, v0 * j * df.determinant()],
                };
            });
        let nb = self.spec.blocks();
        self.average_vol_dj_to_nodes(nb);
        let mk = &self.markers;
        let (origin, dx) = (self.spec.origin, self.spec.dx);
        let grid = &self.grid;
        let nodal = &self.nodal_dj;
        let vol_dj = &self.vol_dj;
        self.df
            .par_iter_mut()
            .zip(self.status.par_iter_mut())
            .zip(mk.x.par_iter())
            .enumerate()
            .with_min_len(MARKERS_PER_TASK)
            .for_each(|(p, ((df, status), x))| {
                let st = Stencil::new((*x).into(), origin, dx);
                let dj_bar = fbar::interpolate(grid, nodal, nb, &st);
                // The marker's own value: `dJ`, or the total `J` (= V0 J / V0).
                let own = vol_dj[p][1] / vol_dj[p][0];
                match fbar::factor(own, dj_bar) {
                    Some(a) => *df *= a,
                    None => *status = BAD_VOLUME,
                }
            });
    }

    /// The markers' `(V, V dJ)` pairs (`self.vol_dj`) averaged onto the nodes
    /// (`self.nodal_dj`), as both F-bar variants need.
    fn average_vol_dj_to_nodes(&mut self, nb: [usize; 3]) {
        let mut nodal = std::mem::take(&mut self.nodal_dj);
        fbar::nodal_average(&self.grid, &self.scratch, &self.vol_dj, nb, &mut nodal);
        self.nodal_dj = nodal;
    }

    /// The plastic variant ([`FBar::PlasticIncrement`]): the step's plastic volume change
    /// `r_p = det F_P' / det F_P` (the return mapping's) replaced by its stencil average
    /// weighted by the markers' volumes at the step's start, `F_P' <- (rbar_p / r_p)^(1/3)
    /// F_P'`, `F_E` kept (so the total `J` changes with it). Reads `self.vol_dj[p] =
    /// (det F_E, det F_P)` of the step's start.
    fn f_bar_plastic(&mut self) {
        let mk = &self.markers;
        self.vol_dj
            .par_iter_mut()
            .enumerate()
            .with_min_len(MARKERS_PER_TASK)
            .for_each(|(p, vd)| {
                let vol = mk.volume0[p] * vd[0] * vd[1];
                let r = mk.fp[p].determinant() / vd[1];
                *vd = [vol, vol * r];
            });
        let nb = self.spec.blocks();
        self.average_vol_dj_to_nodes(nb);
        let (origin, dx) = (self.spec.origin, self.spec.dx);
        let grid = &self.grid;
        let nodal = &self.nodal_dj;
        let vol_dj = &self.vol_dj;
        let mk = &mut self.markers;
        mk.fp
            .par_iter_mut()
            .zip(self.status.par_iter_mut())
            .zip(mk.x.par_iter())
            .enumerate()
            .with_min_len(MARKERS_PER_TASK)
            .for_each(|(p, ((fp, status), x))| {
                let st = Stencil::new((*x).into(), origin, dx);
                let r_bar = fbar::interpolate(grid, nodal, nb, &st);
                match fbar::factor(vol_dj[p][1] / vol_dj[p][0], r_bar) {
                    Some(a) => *fp *= a,
                    None => *status = BAD_VOLUME,
                }
            });
    }

    /// `F_E <- return_mapping(dF_p F_E)` (`F_P` takes what the return gives up). In the
    /// split the yield surface takes this step's pressure of the rows (solved just before,
    /// from the velocities this `dF` integrates: the order G2P, rows, `dF`, return; its
    /// kernel average, `PressureRows::smoothed_pressure`), not the trace of `F_E`, which
    /// carries no stress there.
    fn project(&mut self, dt: f64) {
        let mat = self.material;
        let rows_p = self.pressure.as_deref().map(|r| r.smoothed_pressure());
        let mk = &mut self.markers;
        mk.fe
            .par_iter_mut()
            .zip(mk.fp.par_iter_mut())
            .zip(self.df.par_iter())
            .zip(self.status.par_iter_mut())
            .enumerate()
            .with_min_len(MARKERS_PER_TASK)
            .for_each(|(p, (((fe, fp), df), status))| {
                if *status == 0 {
                    let fe_trial = df * *fe;
                    let projected = match rows_p.map(|r| r.get(p)) {
                        Some(Some(&pressure)) => {
                            mat.project_at_pressure(&fe_trial, fp, pressure, dt)
                        }
                        // the split before its first solve (a transfer of `dt = 0`): no
                        // deformation, and no pressure to return at
                        Some(None) => Some((fe_trial, *fp)),
                        None => mat.project_step(&fe_trial, fp, dt),
                    };
                    match projected {
                        Some((fe1, fp1)) => {
                            *fe = fe1;
                            *fp = fp1;
                        }
                        None => *status = BAD_PROJECTION,
                    }
                }
            });
    }

    /// `x_p <- x_p + dt v_p`, and the finiteness check.
    fn advect(&mut self, dt: f64) {
        let mk = &mut self.markers;
        mk.x.par_iter_mut()
            .zip(mk.v.par_iter())
            .zip(mk.c.par_iter())
            .zip(mk.fe.par_iter())
            .zip(mk.fp.par_iter())
            .zip(self.status.par_iter_mut())
            .with_min_len(MARKERS_PER_TASK)
            .for_each(|(((((x, v), c), fe), fp), status)| {
                *x += v * dt;
                let finite = x.iter().chain(v.iter()).all(|s| s.is_finite())
                    && c.iter()
                        .chain(fe.iter())
                        .chain(fp.iter())
                        .all(|s| s.is_finite());
                if !finite {
                    *status = BAD_STATE;
                }
            });
    }

    /// The first failed marker as [`MpmError::Diverged`].
    fn check_status(&self) -> Result<()> {
        let Some(p) = self
            .status
            .par_iter()
            .with_min_len(MARKERS_PER_TASK)
            .position_first(|&s| s != 0)
        else {
            return Ok(());
        };
        let what = match self.status[p] {
            BAD_PROJECTION => format!(
                "degenerate elastic deformation gradient (det F_E = {:.3e}) in the return mapping",
                self.markers.fe[p].determinant()
            ),
            BAD_VOLUME => format!(
                "non-positive volume change in the F-bar average (det dF = {:.3e})",
                self.df[p].determinant()
            ),
            _ => "non-finite position, velocity or deformation gradient".to_string(),
        };
        Err(MpmError::Diverged {
            marker: p,
            step: self.steps,
            time: self.time,
            what,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::FixedCorotated;

    /// An elastic body of markers filling `[0, n dx]^3` with `mpc` markers per cell per
    /// axis on a lattice, on an open grid of `n + 4` cells.
    fn lattice(n: usize, mpc: usize, mode: FBar) -> MpmBody {
        let dx = 0.1;
        let spec = GridSpec::new([-2.0 * dx; 3], [n + 4; 3], dx)
            .unwrap()
            .with_walls(0, Wall::Open, Wall::Open)
            .with_walls(1, Wall::Open, Wall::Open)
            .with_walls(2, Wall::Open, Wall::Open);
        let mat = FixedCorotated::elastic(1e5, 0.3).unwrap();
        let settings = MpmSettings {
            gravity: [0.0; 3],
            cfl: 0.5,
            f_bar: mode,
        };
        let mut body = MpmBody::new(spec, mat.into(), settings).unwrap();
        let hi = Vector3::repeat(n as f64 * dx);
        body.markers
            .fill_box(Vector3::zeros(), hi, dx / mpc as f64, 1000.0, |_| {
                Vector3::zeros()
            })
            .unwrap();
        body
    }

    #[test]
    fn f_bar_keeps_a_uniform_deformation() {
        // An affine velocity field v = v0 + L x (APIC carries it exactly: C = L) gives every
        // marker the same increment, which F-bar must leave as it is (both forms: the
        // markers start with the same J).
        let l = Matrix3::new(0.3, -0.1, 0.2, 0.05, -0.4, 0.1, -0.2, 0.15, 0.25);
        let v0 = Vector3::new(0.1, -0.2, 0.05);
        let run = |mode: FBar| {
            let mut body = lattice(6, 2, mode);
            let mut s = 0.37f64;
            for p in 0..body.markers.len() {
                // Jitter the markers off the lattice (a uniform field does not care).
                s = (s * 3.7 + 0.13).fract();
                body.markers.x[p] += Vector3::new(s - 0.5, 0.5 - s, 0.3 * s) * 0.02;
                body.markers.v[p] = v0 + l * body.markers.x[p];
                body.markers.c[p] = l;
            }
            body.step(1e-3).unwrap();
            body.markers.fe
        };
        let off = run(FBar::Off);
        let expect = Matrix3::identity() + l * 1e-3;
        for mode in [FBar::Increment, FBar::Total] {
            let on = run(mode);
            for (p, (a, b)) in off.iter().zip(&on).enumerate() {
                assert!((a - b).norm() < 1e-13, "{mode:?}, marker {p}: {a} vs {b}");
                assert!((a - expect).norm() < 1e-12, "marker {p}: {a} vs {expect}");
            }
        }
    }

    #[test]
    fn f_bar_averages_a_checkerboard_of_volume_changes() {
        // Increments dJ = 1 + e s_p with s_p = +-1 alternating from one marker to the next
        // (in 3-D, and in layers along z like the snow column's), one or two markers per
        // cell: inside the block (where every node sees both signs equally) the averaged
        // increment is exactly 1; everywhere the total volume change is kept.
        let e = 0.01;
        for mpc in [1, 2] {
            for layered in [false, true] {
                let n = 8;
                let mut body = lattice(n, mpc, FBar::Increment);
                body.p2g(0.0);
                body.grid_update(0.0);
                body.g2p_velocity(0.0);
                body.status.clear();
                body.status.resize(body.markers.len(), 0);
                let d = 0.1 / mpc as f64;
                let idx = |x: &Vector3<f64>| x.map(|c| (c / d - 0.5).round() as i64);
                let mut before = 0.0;
                for p in 0..body.markers.len() {
                    let i = idx(&body.markers.x[p]);
                    let parity = if layered { i.z } else { i.x + i.y + i.z };
                    let s = if parity % 2 == 0 { 1.0 } else { -1.0 };
                    body.df[p] = Matrix3::from_diagonal(&Vector3::new(1.0 + e * s, 1.0, 1.0));
                    before += body.markers.volume0[p] * (1.0 + e * s);
                }
                body.f_bar_increments(FBar::Increment);
                assert!(body.status.iter().all(|&s| s == 0));
                let mut after = 0.0;
                let mut interior = 0;
                for p in 0..body.markers.len() {
                    let dj = body.df[p].determinant();
                    after += body.markers.volume0[p] * dj;
                    // Interior: every node the marker weighs sees markers up to 1.5 dx on
                    // both sides (3 cells of margin).
                    let x = body.markers.x[p];
                    if x.iter().all(|&c| c > 0.3 && c < n as f64 * 0.1 - 0.3) {
                        interior += 1;
                        assert!(
                            (dj - 1.0).abs() < 1e-13,
                            "mpc {mpc}, layered {layered}, marker {p} at {x:?}: dJ {dj}"
                        );
                    }
                }
                assert!(
                    interior >= 8 * mpc * mpc * mpc,
                    "{interior} interior markers"
                );
                assert!(
                    (after - before).abs() < 1e-12 * before,
                    "total volume change {after} vs {before}"
                );
            }
        }
    }
}
