//! The decomposition's side of an [`SphSystem`]: cutting the scene to a rank's slab,
//! rebuilding ghosts and migrating with the neighbour list, refreshing the ghosts within
//! a step (see [`crate::distributed`]).

use super::SphSystem;
use super::active::ALL;
use crate::data::FLUID;
use crate::distributed::{
    DistributedSettings, MIGRATE_LEN, Refresh, Slabs, Transport, compact, compact_data, pack_state,
    push_state,
};
use crate::error::{Result, SphError};

/// A rank's part of a decomposition.
#[derive(Debug, Clone)]
pub(crate) struct DistState {
    settings: DistributedSettings,
    rank: usize,
    size: usize,
    slabs: Slabs,
    /// Halo width, m: the neighbour-list radius.
    width: f64,
    /// The owning rank of each slot (this rank for owned particles), in slot order.
    pub(crate) owner: Vec<u32>,
    pub(crate) owner_scratch: Vec<u32>,
    /// Per rank: the owned slots it holds as ghosts, by particle id.
    send: Vec<Vec<u32>>,
    /// Per rank: the ghost slots it owns, by particle id.
    recv: Vec<Vec<u32>>,
    sbuf: Vec<Vec<f64>>,
    rbuf: Vec<Vec<f64>>,
    /// Scratch: the values expected from each rank.
    counts: Vec<usize>,
    /// Scratch of the rebuild (kept: no allocation once grown).
    keep: Vec<bool>,
    work: Vec<f64>,
    hist: Vec<f64>,
    pairs: Vec<(u32, u32)>,
    builds: u64,
    stats: HaloStats,
}

/// Counters of a rank's decomposition since the start.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct HaloStats {
    /// Ghost and migration rebuilds (= neighbour-list builds).
    pub builds: u64,
    /// Cut moves (rebalances).
    pub rebalances: u64,
    /// Particles this rank received by migration.
    pub migrated_in: u64,
    /// Particles this rank owns now.
    pub owned: usize,
    /// Ghosts this rank holds now.
    pub ghosts: usize,
    /// Values (`f64`, 8 bytes each) this rank sent to other ranks.
    pub values_sent: u64,
}

impl SphSystem {
    /// Cuts this rank's part out of the whole scene: call it on every rank after
    /// building the same scene, before the first step, with the rank and rank count of
    /// the transport that will step it ([`step_on`](Self::step_on)). The slabs balance
    /// the work ([`Slabs::balanced`], [`DistributedSettings::wall_weight`]).
    ///
    /// Errors, each naming the field: a periodic or unknown `axis`, more ranks than the
    /// scene has slabs (a slab narrower than the halo width), rigid or point marker
    /// carriers (a decomposition would cut a body: not supported), the active domain,
    /// a system already stepped or already distributed, a rank outside `0..size`.
    pub fn distribute(
        &mut self,
        rank: usize,
        size: usize,
        settings: DistributedSettings,
    ) -> Result<()> {
        if rank >= size {
            return Err(SphError::invalid(
                "rank",
                rank,
                format!("must be below the rank count {size}"),
            ));
        }
        if settings.axis > 2 {
            return Err(SphError::invalid(
                "distributed.axis",
                settings.axis,
                "must be 0, 1 or 2",
            ));
        }
        if self.settings.periodic[settings.axis] {
            return Err(SphError::invalid(
                "distributed.axis",
                settings.axis,
                "must not be a periodic axis (slabs are cut along a bounded axis)",
            ));
        }
        if settings.histogram_bins == 0 {
            return Err(SphError::invalid(
                "distributed.histogram_bins",
                0,
                "must be > 0",
            ));
        }
        if !self.carriers.is_empty() || !self.point_carriers.is_empty() {
            return Err(SphError::invalid(
                "carriers",
                self.carriers.len() + self.point_carriers.len(),
                "marker carriers (bodies) cannot be distributed: a slab would cut a body",
            ));
        }
        if self.settings.active_domain.is_some() {
            return Err(SphError::invalid(
                "settings.active_domain",
                "Some",
                "the active domain cannot be combined with a decomposition",
            ));
        }
        if self.settings.open_channel.is_some() {
            return Err(SphError::invalid(
                "settings.open_channel",
                "Some",
                "an open channel cannot be combined with a decomposition yet",
            ));
        }
        if self.initialized || self.dist.is_some() {
            return Err(SphError::invalid(
                "distribute",
                "called twice or after a step",
                "call it once, before the first step",
            ));
        }
        let axis = settings.axis;
        let width = self.list_radius;
        let coords = self.axis_coords(axis);
        if !(settings.wall_weight.is_finite() && settings.wall_weight >= 0.0) {
            return Err(SphError::invalid(
                "distributed.wall_weight",
                settings.wall_weight,
                "must be finite and >= 0",
            ));
        }
        let weights = self.weights(settings.wall_weight);
        let slabs = Slabs::balanced(&coords, &weights, size, width)?;
        let keep: Vec<bool> = coords.iter().map(|&c| slabs.owner(c) == rank).collect();
        compact_data(&mut self.data, &keep);
        self.act = vec![ALL; self.data.len()];
        self.n_fluid = self.data.kind.iter().filter(|&&k| k == FLUID).count();
        self.dist = Some(Box::new(DistState {
            settings,
            rank,
            size,
            slabs,
            width,
            owner: vec![rank as u32; self.data.len()],
            owner_scratch: Vec::new(),
            send: vec![Vec::new(); size],
            recv: vec![Vec::new(); size],
            sbuf: vec![Vec::new(); size],
            rbuf: vec![Vec::new(); size],
            counts: Vec::with_capacity(size),
            keep: Vec::new(),
            work: Vec::new(),
            hist: Vec::new(),
            pairs: Vec::new(),
            builds: 0,
            stats: HaloStats::default(),
        }));
        Ok(())
    }

    /// Whether slot `i` is owned by this rank (always true without a decomposition;
    /// false for a ghost).
    pub fn is_owned(&self, i: usize) -> bool {
        self.dist
            .as_ref()
            .is_none_or(|d| d.owner[i] as usize == d.rank)
    }

    /// This rank (`None` without a decomposition).
    pub fn rank(&self) -> Option<usize> {
        self.dist.as_ref().map(|d| d.rank)
    }

    /// This rank's decomposition counters (`None` without a decomposition).
    pub fn halo_stats(&self) -> Option<HaloStats> {
        self.dist.as_ref().map(|d| {
            let mut s = d.stats;
            s.owned = d.owner.iter().filter(|&&o| o as usize == d.rank).count();
            s.ghosts = d.owner.len() - s.owned;
            s
        })
    }

    /// The slab cut points of the decomposition (`None` without one).
    pub fn slabs(&self) -> Option<&Slabs> {
        self.dist.as_ref().map(|d| &d.slabs)
    }

    /// The balance weight of every particle: 1 for fluid, `wall` for wall markers.
    fn weights(&self, wall: f64) -> Vec<f64> {
        self.data
            .kind
            .iter()
            .map(|&k| if k == FLUID { 1.0 } else { wall })
            .collect()
    }

    /// The coordinate of every particle along `axis`.
    fn axis_coords(&self, axis: usize) -> Vec<f64> {
        let d = &self.data;
        match axis {
            0 => d.x.clone(),
            1 => d.y.clone(),
            _ => d.z.clone(),
        }
    }

    /// The error for stepping a distributed system without its transport (or the
    /// reverse).
    pub(super) fn check_net(&self, net: &Option<&mut (dyn Transport + 'static)>) -> Result<()> {
        match (&self.dist, net) {
            (Some(_), None) => Err(SphError::invalid(
                "transport",
                "none",
                "a distributed system steps with step_on(transport)",
            )),
            (Some(d), Some(t)) if t.rank() != d.rank || t.size() != d.size => {
                Err(SphError::invalid(
                    "transport",
                    format!("rank {} of {}", t.rank(), t.size()),
                    format!(
                        "the system was distributed as rank {} of {}",
                        d.rank, d.size
                    ),
                ))
            }
            (None, Some(_)) => Err(SphError::invalid(
                "transport",
                "some",
                "the system is not distributed: call distribute first",
            )),
            _ => Ok(()),
        }
    }

    /// Drops the ghosts, migrates the owned particles that left the slab (after moving
    /// the cuts when a rebalance is due) and receives the new ghosts. Before a grid
    /// build.
    pub(super) fn halo_rebuild(&mut self, net: &mut dyn Transport) -> Result<()> {
        let Some(mut st) = self.dist.take() else {
            return Ok(());
        };
        let r = self.halo_rebuild_with(&mut st, net);
        self.dist = Some(st);
        r
    }

    fn halo_rebuild_with(&mut self, st: &mut DistState, net: &mut dyn Transport) -> Result<()> {
        let me = st.rank as u32;
        let axis = st.settings.axis;
        // the work of each owned particle from the last list (before its slots move):
        // 1 plus its neighbour entries, times the wall weight for a wall marker (a wall
        // marker far from the fluid costs little, one near it extrapolates once per step)
        let every = st.settings.rebalance_every as u64;
        let due =
            every > 0 && (st.builds == 1 || (st.builds > 0 && st.builds.is_multiple_of(every)));
        st.work.clear();
        if due && self.list.len() == self.data.len() {
            for i in 0..self.data.len() {
                if st.owner[i] == me {
                    let k = if self.data.kind[i] == FLUID {
                        1.0
                    } else {
                        st.settings.wall_weight
                    };
                    st.work
                        .push(k * (1.0 + self.list.neighbors(i).len() as f64));
                }
            }
        }
        // 1. the owned particles only
        st.keep.clear();
        st.keep.extend(st.owner.iter().map(|&o| o == me));
        compact_data(&mut self.data, &st.keep);
        compact(&mut self.act, &st.keep);
        // 2. the cuts at the current quantiles of the work, when due
        if due {
            let new = self.rebalanced(st, net)?;
            if new != st.slabs {
                st.stats.rebalances += 1;
            }
            st.slabs = new;
        }
        // 3. migration
        for b in st.sbuf.iter_mut() {
            b.clear();
        }
        st.keep.clear();
        for i in 0..self.data.len() {
            let o = st.slabs.owner(axis_of(&self.data, axis, i));
            st.keep.push(o == st.rank);
            if o != st.rank {
                pack_state(&self.data, i, &mut st.sbuf[o]);
            }
        }
        compact_data(&mut self.data, &st.keep);
        st.stats.values_sent += sent(&st.sbuf, st.rank);
        net.all_to_all(&st.sbuf, &mut st.rbuf)?;
        for (q, b) in st.rbuf.iter().enumerate() {
            check_len(q, b.len(), MIGRATE_LEN)?;
            for rec in b.chunks_exact(MIGRATE_LEN) {
                push_state(&mut self.data, rec);
                st.stats.migrated_in += 1;
            }
        }
        let n_owned = self.data.len();
        // 4. ghosts: every owned particle within the halo width of another slab
        for b in st.sbuf.iter_mut() {
            b.clear();
        }
        for i in 0..n_owned {
            let c = axis_of(&self.data, axis, i);
            for q in 0..st.size {
                if q != st.rank && st.slabs.near(q, c, st.width) {
                    pack_state(&self.data, i, &mut st.sbuf[q]);
                }
            }
        }
        st.stats.values_sent += sent(&st.sbuf, st.rank);
        net.all_to_all(&st.sbuf, &mut st.rbuf)?;
        st.owner.clear();
        st.owner.resize(n_owned, me);
        for (q, b) in st.rbuf.iter().enumerate() {
            check_len(q, b.len(), MIGRATE_LEN)?;
            for rec in b.chunks_exact(MIGRATE_LEN) {
                push_state(&mut self.data, rec);
                st.owner.push(q as u32);
            }
        }
        // owned: every flag; ghosts: none (frozen, no row, see `active`)
        self.act.clear();
        self.act.resize(n_owned, ALL);
        self.act.resize(self.data.len(), 0);
        self.n_fluid = self.data.kind[..n_owned]
            .iter()
            .filter(|&&k| k == FLUID)
            .count();
        self.x_ref.clear();
        st.builds += 1;
        st.stats.builds = st.builds;
        Ok(())
    }

    /// The cuts at the quantiles of the current positions weighted by `work` (one value
    /// per owned particle; empty: the kind weights): a histogram over the global extent
    /// summed over the ranks.
    fn rebalanced(&self, st: &mut DistState, net: &mut dyn Transport) -> Result<Slabs> {
        let d = &self.data;
        let axis = st.settings.axis;
        let (lo, hi) = (0..d.len()).fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), i| {
            let c = axis_of(d, axis, i);
            (a.min(c), b.max(c))
        });
        let mut ext = [-lo, hi];
        net.all_max(&mut ext)?;
        let (lo, hi) = (-ext[0], ext[1]);
        let bins = st.settings.histogram_bins;
        st.hist.clear();
        st.hist.resize(bins, 0.0);
        let db = (hi - lo) / bins as f64;
        let measured = st.work.len() == d.len();
        for i in 0..d.len() {
            let c = axis_of(d, axis, i);
            let w = if measured {
                st.work[i]
            } else if d.kind[i] == FLUID {
                1.0
            } else {
                st.settings.wall_weight
            };
            let b = if db > 0.0 {
                ((c - lo) / db) as usize
            } else {
                0
            };
            st.hist[b.min(bins - 1)] += w;
        }
        net.all_sum(&mut st.hist)?;
        match Slabs::from_histogram(&st.hist, lo, hi, st.size, st.width) {
            Ok(s) => Ok(s),
            // the particles gathered into fewer slabs than ranks: keep the current cuts
            Err(_) => Ok(st.slabs.clone()),
        }
    }

    /// The send and receive lists at the current slot order (after a list build and its
    /// re-sort), both ordered by particle id.
    pub(super) fn halo_index(&mut self) {
        let Some(st) = self.dist.as_mut() else {
            return;
        };
        let d = &self.data;
        let coords: &[f64] = match st.settings.axis {
            0 => &d.x,
            1 => &d.y,
            _ => &d.z,
        };
        let me = st.rank as u32;
        let pairs = &mut st.pairs;
        for q in 0..st.size {
            pairs.clear();
            if q != st.rank {
                for i in 0..d.len() {
                    if st.owner[i] == me && st.slabs.near(q, coords[i], st.width) {
                        pairs.push((d.id[i], i as u32));
                    }
                }
            }
            pairs.sort_unstable();
            st.send[q].clear();
            st.send[q].extend(pairs.iter().map(|p| p.1));
            pairs.clear();
            for i in 0..d.len() {
                if st.owner[i] == q as u32 && q != st.rank {
                    pairs.push((d.id[i], i as u32));
                }
            }
            pairs.sort_unstable();
            st.recv[q].clear();
            st.recv[q].extend(pairs.iter().map(|p| p.1));
        }
    }

    /// Sends the owned particles' `kind` fields (split borrows: the caller may hold the
    /// grid and list) to the ranks that hold them as ghosts
    /// and sets the ghosts' from what their owners sent.
    pub(super) fn refresh(
        dist: &mut Option<Box<DistState>>,
        data: &mut crate::data::ParticleData,
        kind: Refresh,
        net: &mut dyn Transport,
    ) -> Result<()> {
        let Some(st) = dist.as_mut() else {
            return Ok(());
        };
        let n = kind.len();
        for (q, b) in st.sbuf.iter_mut().enumerate() {
            b.clear();
            for &i in &st.send[q] {
                kind.pack(data, i as usize, b);
            }
        }
        st.stats.values_sent += sent(&st.sbuf, st.rank);
        st.counts.clear();
        st.counts.extend(st.recv.iter().map(|r| r.len() * n));
        net.all_to_all_sized(&st.sbuf, &mut st.rbuf, &st.counts)?;
        for (q, b) in st.rbuf.iter().enumerate() {
            for (rec, &i) in b.chunks_exact(n).zip(&st.recv[q]) {
                kind.unpack(data, i as usize, rec);
            }
        }
        Ok(())
    }

    /// Whether the passes read the activity flags: with the active domain (frozen
    /// particles), an open channel (buffer particles) or a decomposition (ghosts carry no
    /// flag).
    pub(super) fn masked(&self) -> bool {
        self.settings.active_domain.is_some()
            || self.settings.open_channel.is_some()
            || self.dist.is_some()
    }
}

/// The coordinate of slot `i` along `axis`.
#[inline]
fn axis_of(d: &crate::data::ParticleData, axis: usize, i: usize) -> f64 {
    match axis {
        0 => d.x[i],
        1 => d.y[i],
        _ => d.z[i],
    }
}

/// Values in the buffers to other ranks.
fn sent(bufs: &[Vec<f64>], me: usize) -> u64 {
    bufs.iter()
        .enumerate()
        .filter(|(q, _)| *q != me)
        .map(|(_, b)| b.len() as u64)
        .sum()
}

/// A received buffer must hold whole records.
fn check_len(rank: usize, len: usize, rec: usize) -> Result<()> {
    if len.is_multiple_of(rec) {
        Ok(())
    } else {
        Err(SphError::Rank {
            rank,
            reason: format!("sent {len} values, not a whole number of {rec}-value records"),
        })
    }
}

/// Whole-system figures of a (possibly distributed) system, the same on every rank.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GlobalSummary {
    /// Fluid particles over all ranks (each counted once: owners only).
    pub fluid: usize,
    /// Particles (fluid and wall markers) over all ranks.
    pub particles: usize,
    /// Kinetic energy of the fluid `sum m |v|^2 / 2`, J (each rank's sum in its slot
    /// order, then added in rank order).
    pub kinetic_energy: f64,
    /// The largest fluid coordinate along each axis, m.
    pub fluid_max: [f64; 3],
}

impl SphSystem {
    /// [`GlobalSummary`] over every rank (`net`: the transport of a distributed system,
    /// `None` for a whole one). A collective: every rank calls it.
    pub fn global_summary(
        &self,
        net: Option<&mut (dyn Transport + 'static)>,
    ) -> Result<GlobalSummary> {
        self.check_net(&net)?;
        let d = &self.data;
        let (mut fluid, mut all, mut ke) = (0usize, 0usize, 0.0);
        let mut mx = [f64::NEG_INFINITY; 3];
        for i in 0..d.len() {
            if !self.is_owned(i) {
                continue;
            }
            all += 1;
            if d.kind[i] == FLUID {
                fluid += 1;
                ke += 0.5 * d.mass[i] * (d.vx[i] * d.vx[i] + d.vy[i] * d.vy[i] + d.vz[i] * d.vz[i]);
                mx = [mx[0].max(d.x[i]), mx[1].max(d.y[i]), mx[2].max(d.z[i])];
            }
        }
        if let Some(t) = net {
            let mut s = [fluid as f64, all as f64, ke];
            t.all_sum(&mut s)?;
            t.all_max(&mut mx)?;
            (fluid, all, ke) = (s[0] as usize, s[1] as usize, s[2]);
        }
        Ok(GlobalSummary {
            fluid,
            particles: all,
            kinetic_energy: ke,
            fluid_max: mx,
        })
    }
}
