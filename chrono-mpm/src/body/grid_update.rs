//! The grid update ([`MpmBody::grid_update`]): gravity's impulse on the nodes' momenta,
//! then the velocities under the walls' and the rigid bodies' conditions
//! ([`MpmBody::grid_velocities`], also the split's pass over the final velocities).

use super::*;

impl MpmBody {
    /// Grid velocities from momenta, gravity, and the wall conditions: on the nodes on a
    /// face the condition itself ([`Wall`]); the ghost nodes beyond a face take the mirror
    /// image of the velocity at the mirrored node inside (odd for a sticky wall, the
    /// normal component odd for slip and separating contact). The image makes the
    /// interpolated field satisfy the condition *at the face* (zeroing the ghosts instead
    /// puts the quadratic spline's `v(face) = v_1/8`, not 0, and dissipates the energy of
    /// the zeroed ghosts every step: an energy drift of 1.4 % in 10 periods of the elastic
    /// bar at 32 cells, 0.13 % with the image, `docs/mpm.md`). Before the velocities, the
    /// ghosts' mass and momentum are folded into the nodes they mirror
    /// ([`crate::fold`]: 0.044 % with the folded image).
    pub(crate) fn grid_update(&mut self, dt: f64) {
        let g = self.settings.gravity;
        // Momenta with gravity's impulse, then the walls' ghosts folded into their mirror
        // nodes (`crate::fold`).
        self.grid
            .mom
            .par_chunks_mut(BLOCK3)
            .zip(self.grid.mass.par_chunks(BLOCK3))
            .with_min_len(BLOCKS_PER_TASK)
            .for_each(|(mom, mass)| {
                for l in 0..BLOCK3 {
                    for a in 0..3 {
                        mom[l][a] += mass[l] * dt * g[a];
                    }
                }
            });
        self.grid_velocities(true);
    }

    /// The nodes' momenta (in `grid.mom`, mass in `grid.mass`) to velocities under the wall
    /// conditions (see [`Self::grid_update`]): the walls' ghosts folded, the velocities with
    /// each node's wall condition, the rigid bodies' nodes (`rigid`), the ghosts' images.
    pub(crate) fn grid_velocities(&mut self, rigid: bool) {
        let spec = self.spec;
        let nb = spec.blocks();
        if rigid && self.grid.mirror_on {
            // The rigid bodies' mirrored markers join the sums (`body::mirror`).
            self.fold_with_mirrored();
        } else {
            let mut mom = std::mem::take(&mut self.grid.mom);
            let mut prev = std::mem::take(&mut self.grid.prev);
            let mut fmass = std::mem::take(&mut self.grid.fmass);
            fold::fold_walls(
                &spec,
                &self.grid,
                &self.grid.mass,
                &mut prev,
                &mut fmass,
                &mut mom,
            );
            self.grid.mom = mom;
            self.grid.prev = prev;
            self.grid.fmass = fmass;
        }
        walled_velocities(
            &spec,
            &self.grid.active,
            &self.grid.fmass,
            &mut self.grid.mom,
        );
        if rigid && !self.rigid.is_empty() {
            self.rigid_update();
        }
        // The ghost nodes: images of the updated nodes inside.
        self.grid.prev.clear();
        self.grid.prev.extend_from_slice(&self.grid.mom);
        let mut mom = std::mem::take(&mut self.grid.mom);
        let grid = &self.grid;
        let prev = &grid.prev;
        mom.par_chunks_mut(BLOCK3)
            .with_min_len(BLOCKS_PER_TASK)
            .enumerate()
            .for_each(|(k, mom)| {
                let b = unkey(grid.active[k], nb);
                for l in 0..BLOCK3 {
                    let loc = [l / (BLOCK * BLOCK), (l / BLOCK) % BLOCK, l % BLOCK];
                    let mut mirror = [0usize; 3];
                    let mut ghost = [None; 3];
                    for a in 0..3 {
                        let gi = b[a] * BLOCK + loc[a];
                        let i = gi as i64 - GHOST;
                        let n = spec.cells[a] as i64;
                        let (m, side) = if i < 0 {
                            (-i, Some(0))
                        } else if i > n {
                            (2 * n - i, Some(1))
                        } else {
                            (i, None)
                        };
                        mirror[a] = (m.clamp(0, n) + GHOST) as usize;
                        ghost[a] = side;
                    }
                    if ghost.iter().all(Option::is_none) {
                        continue;
                    }
                    if (0..3).any(|a| ghost[a].is_some_and(|s| spec.walls[a][s] == Wall::Open)) {
                        continue;
                    }
                    let key_m = key(
                        [mirror[0] / BLOCK, mirror[1] / BLOCK, mirror[2] / BLOCK],
                        nb,
                    );
                    let vm = match grid.block_index(key_m) {
                        Some(bi) => {
                            let lm = ((mirror[0] % BLOCK) * BLOCK + mirror[1] % BLOCK) * BLOCK
                                + mirror[2] % BLOCK;
                            prev[bi * BLOCK3 + lm]
                        }
                        None => [0.0; 3],
                    };
                    let sticky =
                        (0..3).any(|a| ghost[a].is_some_and(|s| spec.walls[a][s] == Wall::Sticky));
                    let mut v = vm;
                    if sticky {
                        v = [-vm[0], -vm[1], -vm[2]];
                    } else {
                        for a in 0..3 {
                            let Some(side) = ghost[a] else { continue };
                            let toward = if side == 0 { vm[a] < 0.0 } else { vm[a] > 0.0 };
                            match spec.walls[a][side] {
                                Wall::Slip => v[a] = -vm[a],
                                Wall::Separating if toward => v[a] = -vm[a],
                                _ => {}
                            }
                        }
                    }
                    mom[l] = v;
                }
            });
        self.grid.mom = mom;
    }
}

/// Momenta (`mom`, per node of the active blocks) to velocities `mom / mass` under each
/// node's wall condition, in place; a node without mass gets zero.
pub(super) fn walled_velocities(
    spec: &GridSpec,
    active: &[u64],
    mass: &[f64],
    mom: &mut [[f64; 3]],
) {
    let nb = spec.blocks();
    mom.par_chunks_mut(BLOCK3)
        .zip(mass.par_chunks(BLOCK3))
        .with_min_len(BLOCKS_PER_TASK)
        .enumerate()
        .for_each(|(k, (mom, mass))| {
            let b = unkey(active[k], nb);
            for l in 0..BLOCK3 {
                if mass[l] <= 0.0 {
                    mom[l] = [0.0; 3];
                    continue;
                }
                let mut v = [0.0; 3];
                for a in 0..3 {
                    v[a] = mom[l][a] / mass[l];
                }
                apply_node_walls(&mut v, b, l, spec);
                mom[l] = v;
            }
        });
}
