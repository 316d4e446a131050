//! The rigid bodies' share of the grid update ([`MpmBody::rigid_update`]): the sticky
//! bodies' ghosts folded into the nodes outside, each node inside a body given its
//! condition, and each body's impulse summed in a fixed order.

use super::*;

impl MpmBody {
    /// The rigid bodies' contact conditions on the nodes of the box (the ghosts take their
    /// images afterwards): first the sticky bodies' ghosts (nodes inside, with mass) are
    /// folded into the nodes outside their images read ([`crate::fold`]; serial, in block
    /// and node order), then every node inside a body takes its condition, the sticky image
    /// read from the updated nodes ([`crate::rigid`]). Each body's impulse is the momentum
    /// change of the nodes it changed (with the folded masses), summed per block and then
    /// over the blocks in order, the folded nodes' last (the same bits for any thread
    /// count). A body with mirrored markers ([`RigidBody::mirrored_markers`]) has no
    /// ghosts folded; its impulse is the real markers' share of the change of the nodes
    /// within `3 dx` of it (`m^r (v' - v^r)`, [`MpmBody::fold_with_mirrored`]).
    pub(super) fn rigid_update(&mut self) {
        let spec = self.spec;
        let nb = spec.blocks();
        let nr = self.rigid.len();
        let mut links = std::mem::take(&mut self.grid.links);
        fold::rigid_links(&spec, &self.grid, &self.grid.fmass, &self.rigid, &mut links);
        // The links' corrections per node outside: `w_k W m_g` and `-w_k m_g e_g`, with
        // `e_g` the ghost's departure from its image (`crate::fold`).
        let mut folds = std::mem::take(&mut self.grid.folds);
        folds.clear();
        for (s, link) in links.iter().enumerate() {
            let vb = self.rigid[link.body].velocity;
            let mg = self.grid.fmass[link.ghost];
            let mut e = Vector3::from(self.grid.mom[link.ghost]) - vb;
            let mut w_sum = 0.0;
            for c in 0..link.count {
                let w = link.weights[c];
                w_sum += w;
                e += (Vector3::from(self.grid.mom[link.nodes[c]]) - vb) * w;
            }
            for c in 0..link.count {
                let w = link.weights[c];
                folds.push((
                    link.nodes[c],
                    s * 2 + c,
                    w * w_sum * mg,
                    (e * (-w * mg)).into(),
                    link.body,
                ));
            }
        }
        // Unique keys (node, link order): one order for any thread count.
        folds.sort_unstable_by_key(|f| (f.0, f.1));
        // The folded nodes' momentum change per body, in node order.
        let mut fold_j = std::mem::take(&mut self.grid.fold_impulse);
        fold_j.clear();
        fold_j.resize(nr, [0.0; 6]);
        let mut q = 0;
        while q < folds.len() {
            let j = folds[q].0;
            let body = folds[q].4;
            let (mut dm, mut dp) = (0.0, Vector3::zeros());
            while q < folds.len() && folds[q].0 == j {
                dm += folds[q].2;
                dp += Vector3::from(folds[q].3);
                q += 1;
            }
            let mj = self.grid.fmass[j];
            let v0 = Vector3::from(self.grid.mom[j]);
            let mut v: [f64; 3] = (v0 + dp / (mj + dm)).into();
            // The node's own wall conditions still hold.
            let b = unkey(self.grid.active[j / BLOCK3], nb);
            let l = j % BLOCK3;
            apply_node_walls(&mut v, b, l, &spec);
            let dp = (Vector3::from(v) - v0) * mj;
            let loc = [l / (BLOCK * BLOCK), (l / BLOCK) % BLOCK, l % BLOCK];
            let xj = Vector3::from_fn(|a, _| {
                spec.origin[a] + ((b[a] * BLOCK + loc[a]) as f64 - GHOST as f64) * spec.dx
            });
            let dl = (xj - self.rigid[body].position).cross(&dp);
            for a in 0..3 {
                fold_j[body][a] += dp[a];
                fold_j[body][3 + a] += dl[a];
            }
            self.grid.mom[j] = v;
        }
        self.grid.links = links;
        self.grid.folds = folds;

        self.grid.prev.clear();
        self.grid.prev.extend_from_slice(&self.grid.mom);
        self.grid.impulse.clear();
        self.grid
            .impulse
            .resize(self.grid.active.len() * nr, [0.0; 6]);
        let mut mom = std::mem::take(&mut self.grid.mom);
        let mut impulse = std::mem::take(&mut self.grid.impulse);
        let grid = &self.grid;
        let rigid = &self.rigid;
        // The velocity of node `i` of the box, if it has mass.
        let node = |i: [i64; 3]| -> Option<[f64; 3]> {
            if (0..3).any(|a| i[a] < 0 || i[a] > spec.cells[a] as i64) {
                return None;
            }
            let f = fold::flat(grid, nb, i)?;
            (grid.fmass[f] > 0.0).then(|| grid.prev[f])
        };
        mom.par_chunks_mut(BLOCK3)
            .zip(impulse.par_chunks_mut(nr))
            .with_min_len(BLOCKS_PER_TASK)
            .enumerate()
            .for_each(|(k, (mom, impulse))| {
                let b = unkey(grid.active[k], nb);
                let mass = &grid.fmass[k * BLOCK3..(k + 1) * BLOCK3];
                for l in 0..BLOCK3 {
                    if mass[l] <= 0.0 {
                        continue;
                    }
                    let loc = [l / (BLOCK * BLOCK), (l / BLOCK) % BLOCK, l % BLOCK];
                    let i: [i64; 3] =
                        std::array::from_fn(|a| (b[a] * BLOCK + loc[a]) as i64 - GHOST);
                    if (0..3).any(|a| i[a] < 0 || i[a] > spec.cells[a] as i64) {
                        continue;
                    }
                    let x = Vector3::from_fn(|a, _| spec.origin[a] + i[a] as f64 * spec.dx);
                    let mut v = mom[l];
                    for (r, body) in rigid.iter().enumerate() {
                        if mass[l] < body.min_node_mass {
                            continue;
                        }
                        if let Some(v1) = body.contact_velocity(&x, i, spec.dx, v, node) {
                            if !body.mirrors() {
                                let dp = (Vector3::from(v1) - Vector3::from(v)) * mass[l];
                                let dl = (x - body.position).cross(&dp);
                                for a in 0..3 {
                                    impulse[r][a] += dp[a];
                                    impulse[r][3 + a] += dl[a];
                                }
                            }
                            v = v1;
                        }
                    }
                    mom[l] = v;
                    if !grid.mirror_on {
                        continue;
                    }
                    // A mirroring body's impulse: the real markers' share of the node's
                    // change, `m^r (v' - v^r)`, on the nodes within 3 dx of it (those its
                    // mirrored markers reach; to the first such body;
                    // `RigidBody::mirrored_markers`).
                    let q = k * BLOCK3 + l;
                    let mr = grid.real_mass[q];
                    if mr <= 0.0 {
                        continue;
                    }
                    for (r, body) in rigid.iter().enumerate() {
                        if !body.mirrors() {
                            continue;
                        }
                        let (phi, _) = body.shape.distance(&(x - body.position));
                        if phi >= 3.0 * spec.dx {
                            continue;
                        }
                        let dp = (Vector3::from(v) - Vector3::from(grid.real_vel[q])) * mr;
                        let dl = (x - body.position).cross(&dp);
                        for a in 0..3 {
                            impulse[r][a] += dp[a];
                            impulse[r][3 + a] += dl[a];
                        }
                        break;
                    }
                }
            });
        for (r, body) in self.rigid.iter_mut().enumerate() {
            let mut j = [0.0; 6];
            for k in 0..self.grid.active.len() {
                for (c, jc) in j.iter_mut().enumerate() {
                    *jc += impulse[k * nr + r][c];
                }
            }
            for (c, jc) in j.iter_mut().enumerate() {
                *jc += fold_j[r][c];
            }
            body.impulse = Vector3::new(j[0], j[1], j[2]);
            body.total_impulse += body.impulse;
            body.angular_impulse = Vector3::new(j[3], j[4], j[5]);
            body.total_angular_impulse += body.angular_impulse;
        }
        self.grid.mom = mom;
        self.grid.impulse = impulse;
        self.grid.fold_impulse = fold_j;
    }
}
