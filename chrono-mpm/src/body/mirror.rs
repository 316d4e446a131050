//! The mirrored markers of the sticky bodies that use them
//! ([`RigidBody::mirrored_markers`]): their share of P2G ([`MpmBody::p2g_mirrored`]) and
//! the walls' fold with it, keeping the real markers' share alone for the bodies' impulse
//! ([`MpmBody::fold_with_mirrored`]).

use super::*;

impl MpmBody {
    /// P2G's share of the mirrored markers, into `grid.mirror_mass` and `grid.mirror_mom`
    /// (the nodes of the active blocks; nodes of inactive blocks are inside the body,
    /// beyond every real marker's stencil, and take no share). Each marker within
    /// `1.5 dx` of a face of a mirroring body adds its image about that face
    /// ([`RigidBody::mirrored_markers`]): mass `m`, momentum `m (2 v_b - v - dt g)` with
    /// the affine part `-m C R`, and the stress impulse of `-tau R`, `R = I - 2 n n^T`.
    /// Serial, in marker order then body order: the same bits for any thread count.
    pub(super) fn p2g_mirrored(&mut self, dt: f64) {
        let grid = &mut self.grid;
        grid.mirror_on = self.rigid.iter().any(RigidBody::mirrors);
        grid.mirror_mass.clear();
        grid.mirror_mom.clear();
        if !grid.mirror_on {
            return;
        }
        let nodes = grid.mass.len();
        let mut mass = std::mem::take(&mut grid.mirror_mass);
        let mut mom = std::mem::take(&mut grid.mirror_mom);
        mass.resize(nodes, 0.0);
        mom.resize(nodes, [0.0; 3]);
        let spec = self.spec;
        let (origin, dx) = (spec.origin, spec.dx);
        let nb = spec.blocks();
        let reach = 1.5 * dx;
        let g = Vector3::from(self.settings.gravity);
        let mk = &self.markers;
        let mat = self.material;
        let split = self.pressure.is_some();
        let grid = &self.grid;
        for p in 0..mk.len() {
            for body in self.rigid.iter().filter(|r| r.mirrors()) {
                let Some((xm, n)) = body.mirror_marker(&mk.x[p], reach) else {
                    continue;
                };
                let r = Matrix3::identity() - (n * n.transpose()) * 2.0;
                let m = mk.mass[p];
                let tau = mat.grid_stress(&mk.fe[p], &mk.fp[p], split);
                // -dt V0 tau' with tau' = -tau R.
                let am = (tau * r) * (dt * mk.volume0[p]);
                let mv = (body.velocity * 2.0 - mk.v[p] - g * dt) * m;
                let mc = -(mk.c[p] * r) * m;
                let st = Stencil::new(xm.into(), origin, dx);
                for o0 in 0..3 {
                    for o1 in 0..3 {
                        for o2 in 0..3 {
                            let o = [o0, o1, o2];
                            let i: [i64; 3] = std::array::from_fn(|a| st.base[a] + o[a] as i64);
                            if (0..3).any(|a| i[a] < -GHOST || i[a] > spec.cells[a] as i64 + GHOST)
                            {
                                continue;
                            }
                            let Some(f) = fold::flat(grid, nb, i) else {
                                continue;
                            };
                            let w = st.weight(o);
                            let off = Vector3::from(st.offset(o, dx));
                            let gw = Vector3::from(st.grad(o));
                            let dp = (mv + mc * off) * w + am * gw;
                            mass[f] += w * m;
                            for a in 0..3 {
                                mom[f][a] += dp[a];
                            }
                        }
                    }
                }
            }
        }
        self.grid.mirror_mass = mass;
        self.grid.mirror_mom = mom;
    }

    /// The walls' fold with the mirrored markers (when `grid.mirror_on`): the real markers'
    /// folded masses and their velocities under the node walls alone into
    /// `grid.real_mass` and `grid.real_vel`, then the mirrored markers' shares added to
    /// `grid.mom` and the sum folded into `grid.fmass` and `grid.mom`.
    pub(super) fn fold_with_mirrored(&mut self) {
        let spec = self.spec;
        let mut prev = std::mem::take(&mut self.grid.prev);
        let mut real_mass = std::mem::take(&mut self.grid.real_mass);
        let mut real_vel = std::mem::take(&mut self.grid.real_vel);
        real_vel.clear();
        real_vel.extend_from_slice(&self.grid.mom);
        fold::fold_walls(
            &spec,
            &self.grid,
            &self.grid.mass,
            &mut prev,
            &mut real_mass,
            &mut real_vel,
        );
        super::grid_update::walled_velocities(&spec, &self.grid.active, &real_mass, &mut real_vel);
        self.grid.real_mass = real_mass;
        self.grid.real_vel = real_vel;
        // The sums: the mirrored markers' mass array takes the real markers' added.
        let mut mass = std::mem::take(&mut self.grid.mirror_mass);
        let mut mom = std::mem::take(&mut self.grid.mom);
        for (q, m) in mass.iter_mut().enumerate() {
            *m += self.grid.mass[q];
            for a in 0..3 {
                mom[q][a] += self.grid.mirror_mom[q][a];
            }
        }
        let mut fmass = std::mem::take(&mut self.grid.fmass);
        fold::fold_walls(&spec, &self.grid, &mass, &mut prev, &mut fmass, &mut mom);
        self.grid.mom = mom;
        self.grid.prev = prev;
        self.grid.fmass = fmass;
        self.grid.mirror_mass = mass;
    }
}
