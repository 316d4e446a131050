//! [`MpiTransport`]: ranks as MPI processes (cargo feature `mpi`; rsmpi over the
//! system's MPI library).

use mpi::collective::SystemOperation;
use mpi::datatype::{Partition, PartitionMut};
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;

use super::Transport;
use crate::error::{ChronoError, Result};

/// The ranks of an MPI communicator. Build it from the world of
/// `mpi::initialize()` (keep the universe alive for the run):
///
/// ```no_run
/// let universe = mpi::initialize().expect("MPI");
/// let mut t = chrono_core::distributed::MpiTransport::new(universe.world());
/// ```
///
/// All-to-all: the counts by `MPI_Alltoall`, then the values by `MPI_Alltoallv`; max by
/// `MPI_Allreduce`; the sum by `MPI_Allgather` and an addition in rank order (an
/// MPI reduction's order is the library's, so its sum could differ between runs).
pub struct MpiTransport {
    comm: SimpleCommunicator,
    counts: Vec<i32>,
    rcounts: Vec<i32>,
    sdispl: Vec<i32>,
    rdispl: Vec<i32>,
    sflat: Vec<f64>,
    rflat: Vec<f64>,
    scratch: Vec<f64>,
}

impl std::fmt::Debug for MpiTransport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "MpiTransport {{ rank: {}, size: {} }}",
            self.comm.rank(),
            self.comm.size()
        )
    }
}

impl MpiTransport {
    /// A transport over `comm` (usually `universe.world()`).
    pub fn new(comm: SimpleCommunicator) -> Self {
        Self {
            comm,
            counts: Vec::new(),
            rcounts: Vec::new(),
            sdispl: Vec::new(),
            rdispl: Vec::new(),
            sflat: Vec::new(),
            rflat: Vec::new(),
            scratch: Vec::new(),
        }
    }
}

fn count(len: usize) -> Result<i32> {
    i32::try_from(len).map_err(|_| {
        ChronoError::invalid(
            "message",
            len,
            "more than i32::MAX values in one MPI message",
        )
    })
}

impl MpiTransport {
    /// `MPI_Alltoallv` of `send` with the counts in `counts` / `rcounts`.
    fn exchange(&mut self, send: &[Vec<f64>], recv: &mut [Vec<f64>]) -> Result<()> {
        let displ = |c: &[i32], d: &mut Vec<i32>| {
            d.clear();
            let mut a = 0;
            for &k in c {
                d.push(a);
                a += k;
            }
        };
        displ(&self.counts, &mut self.sdispl);
        displ(&self.rcounts, &mut self.rdispl);
        self.sflat.clear();
        for s in send {
            self.sflat.extend_from_slice(s);
        }
        let total: usize = self.rcounts.iter().map(|&c| c as usize).sum();
        self.rflat.clear();
        self.rflat.resize(total, 0.0);
        {
            let p = Partition::new(&self.sflat[..], &self.counts[..], &self.sdispl[..]);
            let mut r = PartitionMut::new(&mut self.rflat[..], &self.rcounts[..], &self.rdispl[..]);
            self.comm.all_to_all_varcount_into(&p, &mut r);
        }
        for (q, r) in recv.iter_mut().enumerate() {
            let (a, c) = (self.rdispl[q] as usize, self.rcounts[q] as usize);
            r.clear();
            r.extend_from_slice(&self.rflat[a..a + c]);
        }
        Ok(())
    }
}

impl Transport for MpiTransport {
    fn rank(&self) -> usize {
        self.comm.rank() as usize
    }

    fn size(&self) -> usize {
        self.comm.size() as usize
    }

    fn all_to_all(&mut self, send: &[Vec<f64>], recv: &mut [Vec<f64>]) -> Result<()> {
        let n = self.size();
        self.counts.clear();
        for s in send {
            self.counts.push(count(s.len())?);
        }
        self.rcounts.clear();
        self.rcounts.resize(n, 0);
        self.comm
            .all_to_all_into(&self.counts[..], &mut self.rcounts[..]);
        self.exchange(send, recv)
    }

    fn all_to_all_sized(
        &mut self,
        send: &[Vec<f64>],
        recv: &mut [Vec<f64>],
        counts: &[usize],
    ) -> Result<()> {
        // the counts are known on both sides: one collective, not two
        self.counts.clear();
        for s in send {
            self.counts.push(count(s.len())?);
        }
        self.rcounts.clear();
        for &c in counts {
            self.rcounts.push(count(c)?);
        }
        self.exchange(send, recv)
    }

    fn all_max(&mut self, v: &mut [f64]) -> Result<()> {
        self.scratch.clear();
        self.scratch.extend_from_slice(v);
        self.comm
            .all_reduce_into(&self.scratch[..], v, SystemOperation::max());
        Ok(())
    }

    fn all_sum(&mut self, v: &mut [f64]) -> Result<()> {
        let n = self.size();
        let m = v.len();
        self.scratch.clear();
        self.scratch.resize(m * n, 0.0);
        self.comm.all_gather_into(&v[..], &mut self.scratch[..]);
        for (i, x) in v.iter_mut().enumerate() {
            let mut acc = self.scratch[i];
            for q in 1..n {
                acc += self.scratch[q * m + i];
            }
            *x = acc;
        }
        Ok(())
    }
}
