//! Consistent boundary images: the ghost nodes' mass and momentum folded into the nodes
//! whose image they take.
//!
//! A ghost node beyond a wall takes the image `v_g = S v_m` of its mirror node `m`
//! (`S` a reflection: `-I` sticky, the normal component flipped for slip; [`Wall`]), and a
//! node inside a sticky rigid body the image `v_g = b - sum_k w_k v_k` of the nodes
//! outside on its normal ([`crate::rigid`]). Those are constraints: the ghost's velocity
//! is not an unknown. The grid update `v = p / m` solves `min sum_i m_i |v_i - p_i/m_i|^2 / 2`
//! (the momentum balance of the lumped grid); under the constraint the minimum over the
//! free nodes is
//!
//! ```text
//! wall:   (m_m + sum_g m_g) v_m = p_m + sum_g S p_g
//! body:   (m_k + sum_g w_k W_g m_g) v_k = p_k + sum_g w_k (m_g b_g - p_g)
//!         (W_g = sum_k w_k, b_g = (1 + W_g) v_b; the mass matrix's rank-one coupling
//!          w w^T m_g lumped by rows, so a rigid motion with the body is kept exactly)
//! ```
//!
//! with `p = m v~` the momentum after P2G (stress and gravity impulses included). The
//! ghosts' stress forces then act on the nodes they mirror instead of being dropped: the
//! images behave like mirrored markers, and a uniform stress is in balance at the
//! boundary nodes (what dropping them breaks; `docs/mpm.md`, `mpm-snow`). The images are
//! then taken as before, from the updated nodes.
//!
//! Separating walls are unilateral: a ghost's normal component is folded reflected when
//! the node then moves into the wall (contact), copied when the node with it copied moves
//! away (lift-off, `S = I`, as the image does), and not folded when neither is consistent.

use nalgebra::Vector3;

use crate::grid::{BLOCK, BLOCK3, GHOST, GridSpec, SparseGrid, Wall, key, unkey};
use crate::rigid::RigidBody;
use rayon::prelude::*;

/// The least grid blocks of one parallel task.
const BLOCKS_PER_TASK: usize = 8;

/// The box node a ghost index `g` of an axis with `n` cells mirrors (the reflection about
/// the face; clamped for boxes thinner than the ghost layers), as the image uses.
#[inline]
pub(crate) fn mirror_index(g: i64, n: i64) -> i64 {
    let m = if g < 0 {
        -g
    } else if g > n {
        2 * n - g
    } else {
        g
    };
    m.clamp(0, n)
}

/// Folds the walls' ghosts into their mirror nodes: `mass` and `mom` are the P2G masses
/// and momenta (gravity included) on the nodes of `grid`'s active blocks; on return
/// `fmass` and `mom` hold, for the box nodes, the folded masses and momenta (ghost nodes
/// unchanged). `prev` is scratch.
pub(crate) fn fold_walls(
    spec: &GridSpec,
    grid: &SparseGrid,
    mass: &[f64],
    prev: &mut Vec<[f64; 3]>,
    fmass: &mut Vec<f64>,
    mom: &mut [[f64; 3]],
) {
    let nb = spec.blocks();
    prev.clear();
    prev.extend_from_slice(mom);
    fmass.clear();
    fmass.extend_from_slice(mass);
    let prev = &*prev;
    fmass
        .par_chunks_mut(BLOCK3)
        .zip(mom.par_chunks_mut(BLOCK3))
        .with_min_len(BLOCKS_PER_TASK)
        .enumerate()
        .for_each(|(k, (fmass, mom))| {
            let b = unkey(grid.active[k], nb);
            for l in 0..BLOCK3 {
                let loc = [l / (BLOCK * BLOCK), (l / BLOCK) % BLOCK, l % BLOCK];
                let i: [i64; 3] = std::array::from_fn(|a| (b[a] * BLOCK + loc[a]) as i64 - GHOST);
                if (0..3).any(|a| i[a] < 0 || i[a] > spec.cells[a] as i64) {
                    continue;
                }
                // Per axis the indices mirroring onto i (itself first) and their side.
                let mut cand = [[(0i64, 2usize); 5]; 3];
                let mut count = [0usize; 3];
                let mut any = false;
                for a in 0..3 {
                    let n = spec.cells[a] as i64;
                    cand[a][0] = (i[a], 2);
                    count[a] = 1;
                    for (side, range) in [(0, -GHOST..0), (1, n + 1..n + 1 + GHOST)] {
                        if spec.walls[a][side] == Wall::Open {
                            continue;
                        }
                        for g in range {
                            if mirror_index(g, n) == i[a] {
                                cand[a][count[a]] = (g, side);
                                count[a] += 1;
                                any = true;
                            }
                        }
                    }
                }
                if !any {
                    continue;
                }
                let mut m = fmass[l];
                let mut p = mom[l];
                // Separating components: the sums of the ghosts' momentum component per
                // (axis, side), decided below.
                let mut sep = [[0.0f64; 2]; 3];
                for c0 in &cand[0][..count[0]] {
                    for c1 in &cand[1][..count[1]] {
                        for c2 in &cand[2][..count[2]] {
                            let c = [*c0, *c1, *c2];
                            if c.iter().all(|c| c.1 == 2) {
                                continue;
                            }
                            let g: [usize; 3] = std::array::from_fn(|a| (c[a].0 + GHOST) as usize);
                            let Some(bi) = grid
                                .block_index(key([g[0] / BLOCK, g[1] / BLOCK, g[2] / BLOCK], nb))
                            else {
                                continue;
                            };
                            let lg = ((g[0] % BLOCK) * BLOCK + g[1] % BLOCK) * BLOCK + g[2] % BLOCK;
                            let mg = mass[bi * BLOCK3 + lg];
                            if mg <= 0.0 {
                                continue;
                            }
                            let pg = prev[bi * BLOCK3 + lg];
                            m += mg;
                            let sticky =
                                (0..3).any(|a| c[a].1 < 2 && spec.walls[a][c[a].1] == Wall::Sticky);
                            for a in 0..3 {
                                if sticky {
                                    p[a] -= pg[a];
                                    continue;
                                }
                                if c[a].1 == 2 {
                                    p[a] += pg[a];
                                    continue;
                                }
                                match spec.walls[a][c[a].1] {
                                    Wall::Slip => p[a] -= pg[a],
                                    Wall::Separating => sep[a][c[a].1] += pg[a],
                                    _ => p[a] += pg[a],
                                }
                            }
                        }
                    }
                }
                // Separating: reflected if the node then moves into that wall (contact),
                // else copied if it then moves away (lift-off), else not folded.
                for a in 0..3 {
                    for side in 0..2 {
                        let s = sep[a][side];
                        if s == 0.0 {
                            continue;
                        }
                        let into = |v: f64| if side == 0 { v < 0.0 } else { v > 0.0 };
                        let other = sep[a][1 - side];
                        if into(p[a] - s - other) {
                            p[a] -= s;
                        } else if !into(p[a] + s - other) {
                            p[a] += s;
                        }
                    }
                }
                fmass[l] = m;
                mom[l] = p;
            }
        });
}

/// A sticky body's ghost node (inside it, with mass) and the nodes its image reads.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Link {
    /// The body.
    pub body: usize,
    /// Flat index (active block * BLOCK3 + node) of the ghost.
    pub ghost: usize,
    /// Flat indices of the nodes outside and their weights, the first `count` used.
    pub nodes: [usize; 2],
    pub weights: [f64; 2],
    pub count: usize,
}

/// The flat index of box node `i` if its block is active.
#[inline]
pub(crate) fn flat(grid: &SparseGrid, nb: [usize; 3], i: [i64; 3]) -> Option<usize> {
    let g: [usize; 3] = std::array::from_fn(|a| (i[a] + GHOST) as usize);
    let bi = grid.block_index(key([g[0] / BLOCK, g[1] / BLOCK, g[2] / BLOCK], nb))?;
    Some(bi * BLOCK3 + ((g[0] % BLOCK) * BLOCK + g[1] % BLOCK) * BLOCK + g[2] % BLOCK)
}

/// Lists the sticky bodies' ghosts whose image reads nodes with mass (`fmass > 0`), in
/// block and node order (the first sticky body containing a node), into `links`. Blocks
/// away from every body are skipped by a bounding-box test.
pub(crate) fn rigid_links(
    spec: &GridSpec,
    grid: &SparseGrid,
    fmass: &[f64],
    rigid: &[RigidBody],
    links: &mut Vec<Link>,
) {
    links.clear();
    let nb = spec.blocks();
    let dx = spec.dx;
    for (k, &bk) in grid.active.iter().enumerate() {
        let b = unkey(bk, nb);
        let lo =
            Vector3::from_fn(|a, _| spec.origin[a] + ((b[a] * BLOCK) as f64 - GHOST as f64) * dx);
        let hi = lo.add_scalar((BLOCK - 1) as f64 * dx);
        let near = |r: &RigidBody| {
            let half = r.shape.bounding_half();
            (0..3).all(|a| lo[a] <= r.position[a] + half[a] && hi[a] >= r.position[a] - half[a])
        };
        if !rigid
            .iter()
            .any(|r| r.uses_image() && !r.mirrors() && near(r))
        {
            continue;
        }
        for l in 0..BLOCK3 {
            let q = k * BLOCK3 + l;
            if fmass[q] <= 0.0 {
                continue;
            }
            let loc = [l / (BLOCK * BLOCK), (l / BLOCK) % BLOCK, l % BLOCK];
            let i: [i64; 3] = std::array::from_fn(|a| (b[a] * BLOCK + loc[a]) as i64 - GHOST);
            if (0..3).any(|a| i[a] < 0 || i[a] > spec.cells[a] as i64) {
                continue;
            }
            let x = Vector3::from_fn(|a, _| spec.origin[a] + i[a] as f64 * dx);
            for (r, body) in rigid.iter().enumerate() {
                if !body.uses_image() {
                    continue;
                }
                let (phi, n) = body.shape.distance(&(x - body.position));
                if phi >= 0.0 {
                    continue;
                }
                if body.mirrors() {
                    // Its ghosts take the mirrored markers' share instead (no fold).
                    break;
                }
                let Some(m) = body.mirror(&x, i, dx, -phi, &n) else {
                    break;
                };
                let mut link = Link {
                    body: r,
                    ghost: q,
                    nodes: [0; 2],
                    weights: [0.0; 2],
                    count: m.count,
                };
                let mut ok = m.count > 0;
                for c in 0..m.count {
                    let j = m.nodes[c];
                    let inside = (0..3).all(|a| j[a] >= 0 && j[a] <= spec.cells[a] as i64);
                    match inside.then(|| flat(grid, nb, j)).flatten() {
                        Some(f) if fmass[f] > 0.0 => {
                            link.nodes[c] = f;
                            link.weights[c] = m.weights[c];
                        }
                        _ => ok = false,
                    }
                }
                if ok {
                    links.push(link);
                }
                break;
            }
        }
    }
}
