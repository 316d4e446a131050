//! The binary encoding of a [`ProblemFile`]: little-endian, length-prefixed arrays (about 8
//! bytes per number), magic `CHRCCP01`; optional trailing sections (the frames, then the
//! rotations and frame-only flags) keep older files readable.

use std::io::{Read, Write};

use super::file::{FrameData, GroupData, MAGIC, MassData, ProblemFile, at};
use super::rows::N_GROUPS;

impl ProblemFile {
    /// Write in the binary encoding.
    pub(super) fn write_binary(&self, w: &mut impl Write) -> std::io::Result<()> {
        w.write_all(MAGIC)?;
        write_bytes(w, self.format.as_bytes())?;
        write_bytes(w, self.description.as_bytes())?;
        w.write_all(&(self.masses.len() as u64).to_le_bytes())?;
        for m in &self.masses {
            let (kind, mass, j) = match m {
                MassData::Particle { mass } => (0u8, *mass, [0.0; 9]),
                MassData::Scalar { mass } => (3u8, *mass, [0.0; 9]),
                MassData::RigidBody { mass, inertia } => (1u8, *mass, *inertia),
                MassData::Dense { matrix, .. } => {
                    // Kind 2: the n^2 values, length-prefixed (n is their square root).
                    w.write_all(&[2u8])?;
                    write_f64s(w, matrix)?;
                    continue;
                }
            };
            w.write_all(&[kind])?;
            w.write_all(&mass.to_le_bytes())?;
            for x in j {
                w.write_all(&x.to_le_bytes())?;
            }
        }
        w.write_all(&(self.groups.len() as u64).to_le_bytes())?;
        for g in &self.groups {
            write_bytes(w, g.group.as_bytes())?;
            write_u32s(w, &g.row_ptr)?;
            write_u32s(w, &g.ent_block)?;
            write_u32s(w, &g.ent_coef)?;
            for v in [&g.coefs, &g.b, &g.eps, &g.lo, &g.hi, &g.mu] {
                write_f64s(w, v)?;
            }
        }
        write_f64s(w, &self.k)?;
        // Frames: an optional trailing section (absent in older files); written (maybe
        // empty) whenever the section after it is.
        let frame_only: Vec<u32> = (self.frames.iter().enumerate())
            .filter(|(_, f)| f.only)
            .map(|(i, _)| i as u32)
            .collect();
        let second = !self.rotations.is_empty() || !frame_only.is_empty();
        if !self.frames.is_empty() || second {
            w.write_all(&(self.frames.len() as u64).to_le_bytes())?;
            for f in &self.frames {
                w.write_all(&f.triplet.to_le_bytes())?;
                for b in f.blocks {
                    w.write_all(&b.unwrap_or(u32::MAX).to_le_bytes())?;
                }
                for x in f.normal.iter().chain(f.arms.iter().flatten()) {
                    w.write_all(&x.to_le_bytes())?;
                }
            }
        }
        // Rotations and frame-only triplets: a second optional section (absent in older
        // files): the rotations (block, x, y, z, w), then the indices of the frame-only
        // frames.
        if second {
            w.write_all(&(self.rotations.len() as u64).to_le_bytes())?;
            for (b, q) in &self.rotations {
                w.write_all(&b.to_le_bytes())?;
                for x in q {
                    w.write_all(&x.to_le_bytes())?;
                }
            }
            write_u32s(w, &frame_only)?;
        }
        Ok(())
    }

    /// Read the binary encoding (after the magic was recognised); a malformed file is an
    /// error naming the field being read.
    pub(super) fn read_binary(r: &mut &[u8]) -> std::io::Result<Self> {
        let mut magic = [0u8; 8];
        r.read_exact(&mut magic).map_err(at("magic"))?;
        let format = read_string(r).map_err(at("format"))?;
        let description = read_string(r).map_err(at("description"))?;
        // The smallest entry is a 1x1 dense block: kind, length, one value.
        let n = read_len_of(r, 1 + 8 + 8).map_err(at("masses.len()"))?;
        let mut masses = Vec::with_capacity(n);
        for i in 0..n {
            let field = |name: &str| at(format!("masses[{i}].{name}"));
            let mut kind = [0u8; 1];
            r.read_exact(&mut kind).map_err(field("kind"))?;
            if kind[0] == 2 {
                let matrix = read_f64s(r).map_err(field("matrix"))?;
                let ndof = matrix.len().isqrt();
                masses.push(MassData::Dense { ndof, matrix });
                continue;
            }
            let mass = read_f64(r).map_err(field("mass"))?;
            let mut j = [0.0; 9];
            for x in &mut j {
                *x = read_f64(r).map_err(field("inertia"))?;
            }
            masses.push(match kind[0] {
                0 => MassData::Particle { mass },
                1 => MassData::RigidBody { mass, inertia: j },
                3 => MassData::Scalar { mass },
                k => {
                    return Err(field("kind")(std::io::Error::other(format!(
                        "unknown mass kind {k} (0 particle, 1 rigid body, 2 dense, 3 scalar)"
                    ))));
                }
            });
        }
        let ng = read_len(r).map_err(at("groups.len()"))?;
        let mut groups = Vec::with_capacity(ng.min(N_GROUPS));
        for gi in 0..ng {
            let field = |name: &str| at(format!("groups[{gi}].{name}"));
            let group = read_string(r).map_err(field("group"))?;
            let row_ptr = read_u32s(r).map_err(field("row_ptr"))?;
            let ent_block = read_u32s(r).map_err(field("ent_block"))?;
            let ent_coef = read_u32s(r).map_err(field("ent_coef"))?;
            let mut f = |name: &str| read_f64s(r).map_err(field(name));
            groups.push(GroupData {
                group,
                row_ptr,
                ent_block,
                ent_coef,
                coefs: f("coefs")?,
                b: f("b")?,
                eps: f("eps")?,
                lo: f("lo")?,
                hi: f("hi")?,
                mu: f("mu")?,
            });
        }
        let k = read_f64s(r).map_err(at("k"))?;
        let mut frames = Vec::new();
        if !r.is_empty() && r.len() < 8 {
            return Err(std::io::Error::other(format!(
                "{} bytes after the last field `k`",
                r.len()
            )));
        }
        if !r.is_empty() {
            let n = read_len_of(r, 4 + 8 + 72).map_err(at("frames.len()"))?;
            for i in 0..n {
                let field = || at(format!("frames[{i}]"));
                let mut u = [0u32; 3];
                for x in &mut u {
                    let mut b = [0u8; 4];
                    r.read_exact(&mut b).map_err(field())?;
                    *x = u32::from_le_bytes(b);
                }
                let mut v = [0.0; 9];
                for x in &mut v {
                    *x = read_f64(r).map_err(field())?;
                }
                let side = |b: u32| (b != u32::MAX).then_some(b);
                frames.push(FrameData {
                    triplet: u[0],
                    blocks: [side(u[1]), side(u[2])],
                    normal: [v[0], v[1], v[2]],
                    arms: [[v[3], v[4], v[5]], [v[6], v[7], v[8]]],
                    only: false,
                });
            }
        }
        let mut rotations = Vec::new();
        if !r.is_empty() {
            let n = read_len_of(r, 4 + 32).map_err(at("rotations.len()"))?;
            for i in 0..n {
                let field = || at(format!("rotations[{i}]"));
                let mut b = [0u8; 4];
                r.read_exact(&mut b).map_err(field())?;
                let mut q = [0.0; 4];
                for x in &mut q {
                    *x = read_f64(r).map_err(field())?;
                }
                rotations.push((u32::from_le_bytes(b), q));
            }
            let nf = frames.len();
            for (i, f) in read_u32s(r)
                .map_err(at("frame_only"))?
                .into_iter()
                .enumerate()
            {
                let frame = frames.get_mut(f as usize).ok_or_else(|| {
                    at(format!("frame_only[{i}]"))(std::io::Error::other(format!(
                        "{f} is not one of the {nf} frames"
                    )))
                })?;
                frame.only = true;
            }
        }
        if !r.is_empty() {
            return Err(std::io::Error::other(format!(
                "{} bytes after the last field `frame_only`",
                r.len()
            )));
        }
        Ok(Self {
            format,
            description,
            masses,
            groups,
            k,
            frames,
            rotations,
        })
    }
}

fn write_bytes(w: &mut impl Write, b: &[u8]) -> std::io::Result<()> {
    w.write_all(&(b.len() as u64).to_le_bytes())?;
    w.write_all(b)
}

fn write_u32s(w: &mut impl Write, v: &[u32]) -> std::io::Result<()> {
    w.write_all(&(v.len() as u64).to_le_bytes())?;
    for x in v {
        w.write_all(&x.to_le_bytes())?;
    }
    Ok(())
}

fn write_f64s(w: &mut impl Write, v: &[f64]) -> std::io::Result<()> {
    w.write_all(&(v.len() as u64).to_le_bytes())?;
    for x in v {
        w.write_all(&x.to_le_bytes())?;
    }
    Ok(())
}

/// An array length, checked against the bytes left (`elem` bytes per element) before
/// anything is allocated: a corrupt or hostile file is an error, not an allocation failure.
fn read_len_of(r: &mut &[u8], elem: usize) -> std::io::Result<usize> {
    let mut b = [0u8; 8];
    r.read_exact(&mut b)?;
    let n = u64::from_le_bytes(b);
    let fits = usize::try_from(n)
        .ok()
        .and_then(|n| n.checked_mul(elem.max(1)))
        .is_some_and(|bytes| bytes <= r.len());
    if !fits {
        return Err(std::io::Error::other(format!(
            "array length {n} exceeds the {} bytes left in the file",
            r.len()
        )));
    }
    Ok(n as usize)
}

fn read_len(r: &mut &[u8]) -> std::io::Result<usize> {
    read_len_of(r, 1)
}

fn read_f64(r: &mut impl Read) -> std::io::Result<f64> {
    let mut b = [0u8; 8];
    r.read_exact(&mut b)?;
    Ok(f64::from_le_bytes(b))
}

fn read_string(r: &mut &[u8]) -> std::io::Result<String> {
    let n = read_len(r)?;
    let mut b = vec![0u8; n];
    r.read_exact(&mut b)?;
    String::from_utf8(b).map_err(std::io::Error::other)
}

fn read_u32s(r: &mut &[u8]) -> std::io::Result<Vec<u32>> {
    let n = read_len_of(r, 4)?;
    let mut raw = vec![0u8; 4 * n];
    r.read_exact(&mut raw)?;
    Ok(raw
        .chunks_exact(4)
        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect())
}

fn read_f64s(r: &mut &[u8]) -> std::io::Result<Vec<f64>> {
    let n = read_len_of(r, 8)?;
    let mut raw = vec![0u8; 8 * n];
    r.read_exact(&mut raw)?;
    Ok(raw
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().expect("8 bytes")))
        .collect())
}
