//! [`LocalTransport`]: ranks as threads of one process (the test double of MPI).

use std::sync::{Arc, Condvar, Mutex};

use super::Transport;
use crate::error::{ChronoError, Result};

#[derive(Debug, Default)]
struct Gate {
    /// Ranks waiting at the current generation.
    waiting: usize,
    generation: u64,
    /// The first rank that left (its transport dropped) before the others.
    left: Option<usize>,
}

#[derive(Debug)]
struct Shared {
    size: usize,
    gate: Mutex<Gate>,
    cv: Condvar,
    /// `boxes[from][to]`.
    boxes: Mutex<Vec<Vec<Vec<f64>>>>,
    red: Mutex<Vec<Vec<f64>>>,
}

/// In-process ranks: each rank is a [`LocalTransport`] used by its own thread. A rank
/// whose transport is dropped while the others still run makes their next collective
/// fail with [`ChronoError::Rank`] naming it (no hang).
#[derive(Debug)]
pub struct LocalTransport {
    rank: usize,
    shared: Arc<Shared>,
}

impl LocalTransport {
    /// `n` connected ranks, `0..n` (move each into its thread).
    pub fn ranks(n: usize) -> Vec<LocalTransport> {
        let shared = Arc::new(Shared {
            size: n,
            gate: Mutex::new(Gate::default()),
            cv: Condvar::new(),
            boxes: Mutex::new(vec![vec![Vec::new(); n]; n]),
            red: Mutex::new(vec![Vec::new(); n]),
        });
        (0..n)
            .map(|rank| LocalTransport {
                rank,
                shared: shared.clone(),
            })
            .collect()
    }

    /// Waits until every rank arrived; an error if a rank left.
    fn barrier(&self) -> Result<()> {
        let s = &self.shared;
        let mut g = s.gate.lock().expect("gate lock");
        if let Some(r) = g.left {
            return Err(left(r));
        }
        let gen_now = g.generation;
        g.waiting += 1;
        if g.waiting == s.size {
            g.waiting = 0;
            g.generation += 1;
            s.cv.notify_all();
            return Ok(());
        }
        while g.generation == gen_now {
            if let Some(r) = g.left {
                return Err(left(r));
            }
            g = s.cv.wait(g).expect("gate wait");
        }
        Ok(())
    }
}

fn left(rank: usize) -> ChronoError {
    ChronoError::Rank {
        rank,
        reason: "left the run before the others (its transport was dropped)".into(),
    }
}

impl Drop for LocalTransport {
    fn drop(&mut self) {
        if let Ok(mut g) = self.shared.gate.lock() {
            if g.left.is_none() {
                g.left = Some(self.rank);
            }
            self.shared.cv.notify_all();
        }
    }
}

impl Transport for LocalTransport {
    fn rank(&self) -> usize {
        self.rank
    }

    fn size(&self) -> usize {
        self.shared.size
    }

    fn all_to_all(&mut self, send: &[Vec<f64>], recv: &mut [Vec<f64>]) -> Result<()> {
        {
            let mut b = self.shared.boxes.lock().expect("boxes lock");
            for (q, s) in send.iter().enumerate() {
                b[self.rank][q].clear();
                b[self.rank][q].extend_from_slice(s);
            }
        }
        self.barrier()?;
        {
            let b = self.shared.boxes.lock().expect("boxes lock");
            for (q, r) in recv.iter_mut().enumerate() {
                r.clear();
                r.extend_from_slice(&b[q][self.rank]);
            }
        }
        self.barrier()
    }

    fn all_max(&mut self, v: &mut [f64]) -> Result<()> {
        self.reduce(v, f64::max)
    }

    fn all_sum(&mut self, v: &mut [f64]) -> Result<()> {
        self.reduce(v, |a, b| a + b)
    }
}

impl LocalTransport {
    /// Element-wise `op` over the ranks in rank order.
    fn reduce(&mut self, v: &mut [f64], op: impl Fn(f64, f64) -> f64) -> Result<()> {
        {
            let mut r = self.shared.red.lock().expect("reduce lock");
            r[self.rank].clear();
            r[self.rank].extend_from_slice(v);
        }
        self.barrier()?;
        {
            let r = self.shared.red.lock().expect("reduce lock");
            for (i, x) in v.iter_mut().enumerate() {
                let mut acc = r[0][i];
                for q in 1..self.shared.size {
                    acc = op(acc, r[q][i]);
                }
                *x = acc;
            }
        }
        self.barrier()
    }
}
