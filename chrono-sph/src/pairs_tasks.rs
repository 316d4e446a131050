//! The rayon tasks of the specialized pair passes ([`super`]): each task runs one pass
//! over a run of particles with the SIMD level the machine has, and the dispatch to the
//! pass monomorphized for the kernel, the density diffusion and the artificial viscosity.

use super::*;

/// Which of the two passes.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Pass {
    Continuity,
    Force,
}

/// One rayon task: the pass over the particles `first..first + out.len()`; `seq` and
/// `len` are their part of the [`Support`] (written by the continuity pass, read by the
/// force pass), `seq` starting at `base(first)`.
struct TaskOp<'a, 'b, const KER: u8, const DIFF: u8, const AV: bool> {
    c: &'a PassCtx<'b>,
    nb: &'a [Packed],
    first: usize,
    out: &'a mut [Deriv],
    /// The force pass's concentration gradients ([`PassCtx::shift`]), one per `out`, or
    /// empty (no shifting, or the continuity pass).
    shift: &'a mut [[f64; 3]],
    seq: &'a mut [u32],
    len: &'a mut [u32],
    pass: Pass,
}

impl<const KER: u8, const DIFF: u8, const AV: bool> WithSimd for TaskOp<'_, '_, KER, DIFF, AV> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: Simd>(self, s: S) -> Self::Output {
        let TaskOp {
            c,
            nb,
            first,
            out,
            shift,
            seq,
            len,
            pass,
        } = self;
        let support2 = c.kernel.support() * c.kernel.support();
        let kc = KConst::new(c);
        let mut tile = Tile::new();
        let b0 = base(c, first);
        for (i, (o, l)) in out.iter_mut().zip(len.iter_mut()).enumerate() {
            let a = first + i;
            let pa = &nb[a];
            let sq = &mut seq[base(c, a) - b0..base(c, a + 1) - b0];
            match pass {
                Pass::Continuity => continuity_one::<S, KER, DIFF>(
                    s, c, nb, pa, a, kc, support2, &mut tile, o, sq, l,
                ),
                Pass::Force => force_one::<S, KER, AV>(
                    s,
                    c,
                    pa,
                    kc,
                    &mut tile,
                    o,
                    shift.get_mut(i),
                    nb,
                    &sq[..*l as usize],
                ),
            }
        }
    }
}

/// Runs `pass` over every particle with the SIMD level `arch` picks.
fn run<const KER: u8, const DIFF: u8, const AV: bool>(
    arch: Option<Arch>,
    nb: &[Packed],
    c: &PassCtx<'_>,
    deriv: &mut [Deriv],
    shift: &mut [[f64; 3]],
    sup: &mut Support,
    pass: Pass,
) {
    let n = deriv.len();
    debug_assert_eq!(c.list.len(), n);
    if pass == Pass::Continuity {
        sup.seq.resize(base(c, n), 0);
        sup.len.resize(n, 0);
    }
    debug_assert!(sup.seq.len() == base(c, n) && sup.len.len() == n);
    debug_assert!(shift.is_empty() || shift.len() == n);
    split::<KER, DIFF, AV>(
        arch,
        nb,
        c,
        0,
        deriv,
        shift,
        &mut sup.seq,
        &mut sup.len,
        pass,
    );
}

/// The particles `first..first + out.len()` in [`CHUNK`]-particle tasks, split in
/// halves with `rayon::join` (each half takes its own part of the [`Support`] buffers:
/// disjoint, no allocation).
#[allow(clippy::too_many_arguments)]
fn split<const KER: u8, const DIFF: u8, const AV: bool>(
    arch: Option<Arch>,
    nb: &[Packed],
    c: &PassCtx<'_>,
    first: usize,
    out: &mut [Deriv],
    shift: &mut [[f64; 3]],
    seq: &mut [u32],
    len: &mut [u32],
    pass: Pass,
) {
    let n = out.len();
    if n <= CHUNK {
        let op = TaskOp::<KER, DIFF, AV> {
            c,
            nb,
            first,
            out,
            shift,
            seq,
            len,
            pass,
        };
        match arch {
            Some(arch) => arch.dispatch(op),
            None => op.with_simd(pulp::Scalar::new()),
        }
        return;
    }
    let mid = (n / CHUNK / 2).max(1) * CHUNK;
    let (o0, o1) = out.split_at_mut(mid);
    let (h0, h1) = if shift.is_empty() {
        (&mut [][..], &mut [][..])
    } else {
        shift.split_at_mut(mid)
    };
    let (s0, s1) = seq.split_at_mut(base(c, first + mid) - base(c, first));
    let (l0, l1) = len.split_at_mut(mid);
    rayon::join(
        || split::<KER, DIFF, AV>(arch, nb, c, first, o0, h0, s0, l0, pass),
        || split::<KER, DIFF, AV>(arch, nb, c, first + mid, o1, h1, s1, l1, pass),
    );
}

/// Picks the monomorphized pass for the context's kernel, diffusion and artificial
/// viscosity.
fn select(
    arch: Option<Arch>,
    nb: &[Packed],
    c: &PassCtx<'_>,
    deriv: &mut [Deriv],
    shift: &mut [[f64; 3]],
    sup: &mut Support,
    pass: Pass,
) {
    let av = c.alpha > 0.0;
    macro_rules! go {
        ($ker:expr) => {
            match (c.diffusion, av) {
                (DensityDiffusion::None, false) => {
                    run::<$ker, DIFF_NONE, false>(arch, nb, c, deriv, shift, sup, pass)
                }
                (DensityDiffusion::None, true) => {
                    run::<$ker, DIFF_NONE, true>(arch, nb, c, deriv, shift, sup, pass)
                }
                (DensityDiffusion::MolteniColagrossi, false) => {
                    run::<$ker, DIFF_MC, false>(arch, nb, c, deriv, shift, sup, pass)
                }
                (DensityDiffusion::MolteniColagrossi, true) => {
                    run::<$ker, DIFF_MC, true>(arch, nb, c, deriv, shift, sup, pass)
                }
                (DensityDiffusion::Fourtakas, false) => {
                    run::<$ker, DIFF_FOURTAKAS, false>(arch, nb, c, deriv, shift, sup, pass)
                }
                (DensityDiffusion::Fourtakas, true) => {
                    run::<$ker, DIFF_FOURTAKAS, true>(arch, nb, c, deriv, shift, sup, pass)
                }
            }
        };
    }
    match c.kernel.kind() {
        KernelKind::WendlandC2 => go!(WENDLAND),
        KernelKind::CubicSpline => go!(CUBIC),
    }
}

/// The continuity pass (see [`interact::continuity_pass`](crate::interact)), specialized
/// and SIMD; `simd = false` runs the one-lane path (the reference arithmetic). Records
/// each fluid particle's in-support neighbours in `sup` for [`force_pass`].
pub(crate) fn continuity_pass(
    nb: &[Packed],
    c: &PassCtx<'_>,
    deriv: &mut [Deriv],
    sup: &mut Support,
    simd: bool,
) {
    select(
        simd.then(Arch::new),
        nb,
        c,
        deriv,
        &mut [],
        sup,
        Pass::Continuity,
    );
}

/// The force pass (see [`interact::force_pass`](crate::interact)), specialized and SIMD;
/// `simd = false` runs the one-lane path. `sup`: recorded by [`continuity_pass`] at the
/// same positions and list, with the same `simd` (the padding depends on the lane
/// count); the records `nb` may differ in everything but the positions. `shift`: empty,
/// or one entry per particle for the shifting's concentration gradient (m^-1, see
/// [`PassCtx::shift`]; zero for wall markers and frozen particles).
pub(crate) fn force_pass(
    nb: &[Packed],
    c: &PassCtx<'_>,
    deriv: &mut [Deriv],
    shift: &mut [[f64; 3]],
    sup: &mut Support,
    simd: bool,
) {
    select(simd.then(Arch::new), nb, c, deriv, shift, sup, Pass::Force);
}
