//! The neighbour search of an [`SphSystem`]: the Verlet criterion, the grid build, the
//! re-sort by cell and the CSR list (rows for the listed particles only when the passes
//! read the activity flags), with the open channel's exchange of particles before it.

use std::time::Instant;

use rayon::prelude::*;

use super::SphSystem;
use super::active::LISTED;
use crate::data::FLUID;
use crate::distributed::Transport;
use crate::error::Result;

impl SphSystem {
    /// Whether some particle moved more than half the skin since the last list build.
    fn list_is_stale(&self) -> bool {
        if self.x_ref.len() != self.data.len() {
            return true;
        }
        let half_skin = 0.5 * (self.list_radius - self.kernel.support());
        let lim2 = half_skin * half_skin;
        let d = &self.data;
        let grid = &self.grid;
        (0..d.len()).into_par_iter().with_min_len(4096).any(|i| {
            let r = self.x_ref[i];
            let e = grid.displacement([d.x[i], d.y[i], d.z[i]], r);
            e[0] * e[0] + e[1] * e[1] + e[2] * e[2] > lim2
        })
    }

    /// Grid build, re-sort by cell when due, CSR neighbour list (radius `2 h (1 + skin)`)
    /// at the current positions; skipped while the Verlet list is still valid.
    pub(super) fn neighbor_search(
        &mut self,
        mut net: Option<&mut (dyn Transport + 'static)>,
    ) -> Result<()> {
        let t0 = Instant::now();
        let mut stale = self.list_is_stale() || self.activity_needs_rebuild();
        if let Some(t) = net.as_deref_mut() {
            // a global decision: every rank rebuilds (ghosts and migration) together
            let mut v = [stale as u8 as f64];
            t.all_max(&mut v)?;
            stale = v[0] > 0.0;
        }
        if !stale {
            self.timings.neighbor_search += t0.elapsed().as_secs_f64();
            return Ok(());
        }
        if let Some(t) = net {
            self.halo_rebuild(t)?;
        }
        self.open_exchange();
        {
            let d = &self.data;
            self.grid.build([&d.x, &d.y, &d.z])?;
        }
        let every = self.settings.reorder_every as u64;
        if every > 0 && (self.steps == 0 || self.steps >= self.last_reorder + every) {
            self.data.permute(self.grid.order());
            chrono_core::particles::permute(
                self.grid.order(),
                &mut self.act,
                &mut self.act_scratch,
            );
            if let Some(st) = self.dist.as_mut() {
                chrono_core::particles::permute(
                    self.grid.order(),
                    &mut st.owner,
                    &mut st.owner_scratch,
                );
            }
            self.grid.reordered();
            self.last_reorder = self.steps;
        }
        self.mark_listed();
        {
            let d = &self.data;
            let kind = &d.kind;
            // wall markers keep only their fluid neighbours: no pass reads wall-wall
            // entries (the wall extrapolation sums over fluid neighbours only)
            let keep = |i: usize, j: usize| kind[i] == FLUID || kind[j] == FLUID;
            if self.masked() {
                // the active domain: rows for the listed particles only
                let act = &self.act;
                self.grid.neighbor_list_rows(
                    [&d.x, &d.y, &d.z],
                    self.list_radius,
                    &mut self.list,
                    |i| act[i] & LISTED != 0,
                    keep,
                )?;
            } else {
                self.grid.neighbor_list_filtered(
                    [&d.x, &d.y, &d.z],
                    self.list_radius,
                    &mut self.list,
                    keep,
                )?;
            }
            self.x_ref.resize(d.len(), [0.0; 3]);
            self.x_ref
                .par_iter_mut()
                .enumerate()
                .for_each(|(i, r)| *r = [d.x[i], d.y[i], d.z[i]]);
        }
        self.halo_index();
        self.stats.neighbor_entries = self.list.total();
        self.stats.list_builds += 1;
        self.timings.neighbor_search += t0.elapsed().as_secs_f64();
        Ok(())
    }
}
