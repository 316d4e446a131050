//! Problem files: a [`CcpProblem`] written to and read from a file, so that hard problems
//! captured from scenes become regression tests and bench inputs.
//!
//! A file holds what the problem was assembled from — the variables (mass operators), the
//! rows of each group (entries, `b`, `eps`, bounds, friction coefficients) and the momentum
//! `k` — and loading assembles it again: assembly is deterministic and validates its input,
//! so a reloaded problem is bit-for-bit the saved one (`N`, `r`, `diag`, ...), and a corrupt
//! file is an error naming the field, never a problem with dangling indices.
//!
//! Two encodings of the same [`ProblemFile`] (serde): JSON (readable; floats are written
//! with the shortest round-trip representation and parsed exactly) and a compact binary one
//! (little-endian, length-prefixed arrays; about 8 bytes per number).

use std::io::Write;
use std::path::Path;

use nalgebra::{Matrix3, Quaternion, UnitQuaternion};
use serde::{Deserialize, Serialize};

use super::problem::{CcpProblem, GROUP_ORDER, group_name};
use super::rows::{
    ConstraintRows, ContactFrame, FrameKind, N_GROUPS, PER_BODY_ROWS, RowGroup, RowId,
};
use super::variables::{BlockId, MassOperator, Variables};
use crate::error::{ChronoError, Result};

/// The format tag written in every file.
pub const FORMAT_TAG: &str = "chrono-rs ccp problem v1";

pub(super) const MAGIC: &[u8; 8] = b"CHRCCP01";

/// The encoding of a problem file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum ProblemFormat {
    /// serde_json text.
    Json,
    /// Little-endian binary (magic `CHRCCP01`).
    Binary,
}

impl ProblemFormat {
    /// The format of a path by extension: `.json` is JSON, anything else binary.
    pub fn from_path(path: &Path) -> Self {
        match path.extension().and_then(|e| e.to_str()) {
            Some("json") => ProblemFormat::Json,
            _ => ProblemFormat::Binary,
        }
    }
}

/// The mass operator of one block, as stored.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum MassData {
    /// A particle of mass `mass` (kg).
    Particle {
        /// kg
        mass: f64,
    },
    /// A 1-dof scalar block (kg or kg m^2), see
    /// [`MassOperator::Scalar`](super::MassOperator::Scalar).
    Scalar {
        /// kg or kg m^2
        mass: f64,
    },
    /// A rigid body: mass (kg) and body-frame inertia (kg m^2, row-major 3x3).
    RigidBody {
        /// kg
        mass: f64,
        /// kg m^2, row-major.
        inertia: [f64; 9],
    },
    /// A coupled block saved as its dense symmetric matrix (kg, row-major `n x n`),
    /// reloaded as a [`DenseMass`](super::DenseMass).
    Dense {
        /// Number of dof `n`.
        ndof: usize,
        /// kg, row-major, `n^2` values.
        matrix: Vec<f64>,
    },
}

/// The rows of one group, as stored (CSR: `row_ptr` into the entries; each entry a block
/// and the start of its coefficients in `coefs`).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct GroupData {
    /// Group name (`bilateral`, `box`, `unilateral`, `friction`, `rolling`,
    /// `rolling_per_body`).
    pub group: String,
    /// Entries of row `i`: `row_ptr[i]..row_ptr[i+1]` (length rows + 1).
    pub row_ptr: Vec<u32>,
    /// Block of each entry.
    pub ent_block: Vec<u32>,
    /// Start of each entry's coefficients.
    pub ent_coef: Vec<u32>,
    /// Coefficients of `D_i'`.
    pub coefs: Vec<f64>,
    /// Right-hand sides `b` (m/s).
    pub b: Vec<f64>,
    /// Compliances `eps`.
    pub eps: Vec<f64>,
    /// Box lower bounds (box group).
    pub lo: Vec<f64>,
    /// Box upper bounds (box group).
    pub hi: Vec<f64>,
    /// Friction coefficients (one per triplet; three per rolling or per-body rolling contact).
    pub mu: Vec<f64>,
}

/// A saved CCP: see the module documentation. Build it with
/// [`from_problem`](Self::from_problem), turn it back into a problem with
/// [`to_problem`](Self::to_problem); [`save`](Self::save) / [`load`](Self::load) do the IO.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ProblemFile {
    /// The format tag, `chrono-rs ccp problem v1` (checked on load).
    pub format: String,
    /// Free text: where the problem came from.
    pub description: String,
    /// One mass operator per variable block.
    pub masses: Vec<MassData>,
    /// The rows, one entry per group in the order bilateral, box, unilateral, friction,
    /// rolling, rolling_per_body (files written before the per-body group have five: it is
    /// then empty).
    pub groups: Vec<GroupData>,
    /// Momentum `k = M v + h f` (N s).
    pub k: Vec<f64>,
    /// The contact frames of friction triplets ([`ContactFrame`]), so that a reloaded
    /// problem applies `N` the same way (matrix-free where the frames qualify) and stays
    /// bit-for-bit the saved one; empty in files written before frames existed.
    #[serde(default)]
    pub frames: Vec<FrameData>,
    /// The rotations of the blocks given with one
    /// ([`Variables::add_oriented`](super::Variables::add_oriented)): block and unit
    /// quaternion `(x, y, z, w)`, which frame-only triplets' rows are built from; empty in
    /// files written before them.
    #[serde(default)]
    pub rotations: Vec<(u32, [f64; 4])>,
}

/// A stored [`ContactFrame`] of the friction triplet `triplet` (its index in the friction
/// group).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FrameData {
    /// Index of the triplet in the friction group.
    pub triplet: u32,
    /// Unit normal (world).
    pub normal: [f64; 3],
    /// Blocks of sides A and B (`None`: no variables).
    pub blocks: [Option<u32>; 2],
    /// Lever arms of A and B (world, m).
    pub arms: [[f64; 3]; 2],
    /// A frame-only triplet (its rows have no entries: they are built from the frame and
    /// the blocks' rotations, `ConstraintRows::push_friction_frame`); false in files
    /// written before them.
    #[serde(default)]
    pub only: bool,
}

impl ProblemFile {
    /// Capture `problem` (with a free-text `description`).
    pub fn from_problem(problem: &CcpProblem, description: impl Into<String>) -> Self {
        let vars = problem.variables();
        let masses = (0..vars.len())
            .map(|b| match vars.mass(BlockId(b as u32)) {
                MassOperator::Particle { mass } => MassData::Particle { mass: *mass },
                MassOperator::Scalar { mass } => MassData::Scalar { mass: *mass },
                MassOperator::RigidBody { mass, inertia, .. } => {
                    let mut j = [0.0; 9];
                    for r in 0..3 {
                        for c in 0..3 {
                            j[3 * r + c] = inertia[(r, c)];
                        }
                    }
                    MassData::RigidBody {
                        mass: *mass,
                        inertia: j,
                    }
                }
                MassOperator::Coupled(op) => {
                    let m = super::coupled::dense_matrix(op.as_ref());
                    // Row-major: the transpose's column-major storage.
                    MassData::Dense {
                        ndof: m.nrows(),
                        matrix: m.transpose().as_slice().to_vec(),
                    }
                }
            })
            .collect();
        let rows = problem.constraint_rows();
        let groups = GROUP_ORDER
            .iter()
            .map(|&g| {
                let src = &rows.groups[g as usize];
                GroupData {
                    group: group_name(g).to_string(),
                    row_ptr: src.row_ptr.clone(),
                    ent_block: src.ent_block.clone(),
                    ent_coef: src.ent_coef.clone(),
                    coefs: src.coefs.clone(),
                    b: src.b.clone(),
                    eps: src.eps.clone(),
                    lo: src.lo.clone(),
                    hi: src.hi.clone(),
                    mu: src.mu.clone(),
                }
            })
            .collect();
        let g = &rows.groups[RowGroup::Friction as usize];
        let frames = (g.frames.iter().zip(&g.frame_kind))
            .map(|(&(triplet, f), &kind)| FrameData {
                triplet,
                normal: f.normal,
                blocks: f.blocks.map(|b| b.map(|b| b.0)),
                arms: f.arms,
                only: kind == FrameKind::Only,
            })
            .collect();
        let rotations = (0..vars.len() as u32)
            .filter_map(|b| {
                let q = vars.rotation(BlockId(b))?;
                Some((b, [q.i, q.j, q.k, q.w]))
            })
            .collect();
        Self {
            format: FORMAT_TAG.to_string(),
            description: description.into(),
            masses,
            groups,
            k: problem.momentum().to_vec(),
            frames,
            rotations,
        }
    }

    /// Assemble the problem (validated: a malformed file is an error naming the field).
    pub fn to_problem(&self) -> Result<CcpProblem> {
        if self.format != FORMAT_TAG {
            return Err(ChronoError::invalid(
                "problem file format",
                &self.format,
                format!("expected `{FORMAT_TAG}`"),
            ));
        }
        let mut rotation = vec![None; self.masses.len()];
        for (i, &(b, q)) in self.rotations.iter().enumerate() {
            let slot = rotation.get_mut(b as usize).ok_or_else(|| {
                ChronoError::invalid(
                    format!("rotations[{i}].block"),
                    b,
                    format!("must name one of the {} variable blocks", self.masses.len()),
                )
            })?;
            let norm = q.iter().map(|x| x * x).sum::<f64>().sqrt();
            if !q.iter().all(|x| x.is_finite()) || (norm - 1.0).abs() > 1e-9 {
                return Err(ChronoError::invalid(
                    format!("rotations[{i}].quaternion"),
                    format!("{q:?}"),
                    "must be a finite unit quaternion",
                ));
            }
            // (kept as stored, not renormalized: the same rows, bit for bit)
            *slot = Some(UnitQuaternion::new_unchecked(Quaternion::new(
                q[3], q[0], q[1], q[2],
            )));
        }
        let mut vars = Variables::new();
        for (i, m) in self.masses.iter().enumerate() {
            let op = match m {
                MassData::Particle { mass } => MassOperator::particle(*mass),
                MassData::Scalar { mass } => MassOperator::scalar(*mass),
                MassData::RigidBody { mass, inertia } => {
                    MassOperator::rigid_body(*mass, Matrix3::from_row_slice(inertia))
                }
                MassData::Dense { ndof, matrix } => dense_block(*ndof, matrix),
            }
            .map_err(|e| ChronoError::invalid(format!("masses[{i}]"), e, "invalid mass"))?;
            match rotation[i] {
                Some(q) => vars.add_oriented(op, q),
                None => vars.add(op),
            };
        }
        // Five groups: a file from before the per-body rolling group (which is then empty).
        if self.groups.len() != N_GROUPS && self.groups.len() != N_GROUPS - 1 {
            return Err(ChronoError::invalid(
                "groups.len()",
                self.groups.len(),
                format!(
                    "must be {N_GROUPS} (or {} without rolling_per_body)",
                    N_GROUPS - 1
                ),
            ));
        }
        let mut rows = ConstraintRows::new();
        for (gi, (&g, data)) in GROUP_ORDER.iter().zip(&self.groups).enumerate() {
            let name = group_name(g);
            if data.group != name {
                return Err(ChronoError::invalid(
                    format!("groups[{gi}].group"),
                    &data.group,
                    format!("expected `{name}`"),
                ));
            }
            check_group(name, data)?;
            if let Some(&blk) = data
                .ent_block
                .iter()
                .find(|&&b| b as usize >= self.masses.len())
            {
                return Err(ChronoError::invalid(
                    format!("groups.{name}.ent_block"),
                    blk,
                    format!(
                        "must name one of the {} variable blocks (masses)",
                        self.masses.len()
                    ),
                ));
            }
            let dst = &mut rows.groups[g as usize];
            dst.row_ptr.clone_from(&data.row_ptr);
            dst.ent_block.clone_from(&data.ent_block);
            dst.ent_coef.clone_from(&data.ent_coef);
            dst.coefs.clone_from(&data.coefs);
            dst.b.clone_from(&data.b);
            dst.eps.clone_from(&data.eps);
            dst.lo.clone_from(&data.lo);
            dst.hi.clone_from(&data.hi);
            dst.mu.clone_from(&data.mu);
        }
        let n_triplets = rows.n_rows(RowGroup::Friction) / 3;
        for (i, f) in self.frames.iter().enumerate() {
            let bad_block = f
                .blocks
                .iter()
                .flatten()
                .find(|&&b| b as usize >= self.masses.len());
            if let Some(&b) = bad_block {
                return Err(ChronoError::invalid(
                    format!("frames[{i}].blocks"),
                    b,
                    format!("must name one of the {} variable blocks", self.masses.len()),
                ));
            }
            if f.triplet as usize >= n_triplets {
                return Err(ChronoError::invalid(
                    format!("frames[{i}].triplet"),
                    f.triplet,
                    format!("must be below the {n_triplets} friction triplets"),
                ));
            }
            let id = RowId {
                group: RowGroup::Friction,
                index: 3 * f.triplet,
            };
            let frame = ContactFrame {
                normal: f.normal,
                blocks: f.blocks.map(|b| b.map(BlockId)),
                arms: f.arms,
            };
            if f.only {
                // its rows are the frame's: they must have no entries of their own
                let g = &rows.groups[RowGroup::Friction as usize];
                let t = 3 * f.triplet as usize;
                if g.row_ptr[t + 3] != g.row_ptr[t] {
                    return Err(ChronoError::invalid(
                        format!("frames[{i}].only"),
                        true,
                        "a frame-only triplet's rows must have no entries",
                    ));
                }
                let before = rows.groups[RowGroup::Friction as usize].frames.len();
                rows.push_frame(id, frame, FrameKind::Only);
                if rows.groups[RowGroup::Friction as usize].frames.len() == before {
                    return Err(ChronoError::invalid(
                        format!("frames[{i}].triplet"),
                        f.triplet,
                        "frames must come in increasing triplet order",
                    ));
                }
            } else {
                rows.set_contact_frame(id, frame);
            }
        }
        let mut p = CcpProblem::new();
        p.assemble(&vars, &rows, &self.k)?;
        Ok(p)
    }

    /// Write to `path` in `format`.
    pub fn save(&self, path: impl AsRef<Path>, format: ProblemFormat) -> Result<()> {
        let path = path.as_ref();
        let io = |e: std::io::Error| io_error(path, e);
        let file = std::fs::File::create(path).map_err(io)?;
        let mut w = std::io::BufWriter::new(file);
        match format {
            ProblemFormat::Json => serde_json::to_writer(&mut w, self)
                .map_err(|e| io_error(path, std::io::Error::other(e)))?,
            ProblemFormat::Binary => self.write_binary(&mut w).map_err(io)?,
        }
        w.flush().map_err(io)
    }

    /// Read from `path` (format detected from the content: binary files start with the magic
    /// `CHRCCP01`, anything else is parsed as JSON).
    pub fn load(path: impl AsRef<Path>) -> Result<Self> {
        let path = path.as_ref();
        let bytes = std::fs::read(path).map_err(|e| io_error(path, e))?;
        Self::parse(&bytes).map_err(|e| io_error(path, e))
    }

    /// Read from the bytes of a file (format detected as in [`load`](Self::load)). A
    /// malformed file is an error whose message names the field being read (its path in
    /// the JSON document, e.g. `groups[2].b[7]`, or in the binary layout, e.g.
    /// `masses[3].inertia`); the problem itself is validated by
    /// [`to_problem`](Self::to_problem).
    pub fn from_bytes(bytes: &[u8]) -> Result<Self> {
        Self::parse(bytes).map_err(|e| ChronoError::invalid("problem file", "bytes", e.to_string()))
    }

    fn parse(bytes: &[u8]) -> std::io::Result<Self> {
        if bytes.starts_with(MAGIC) {
            Self::read_binary(&mut &bytes[..])
        } else {
            let de = &mut serde_json::Deserializer::from_slice(bytes);
            serde_path_to_error::deserialize(de).map_err(|e| {
                let path = e.path().to_string();
                std::io::Error::other(format!("`{path}`: {}", e.into_inner()))
            })
        }
    }

    /// Save `problem` to `path` (format by extension, [`ProblemFormat::from_path`]).
    pub fn save_problem(
        problem: &CcpProblem,
        description: &str,
        path: impl AsRef<Path>,
    ) -> Result<()> {
        let path = path.as_ref();
        Self::from_problem(problem, description).save(path, ProblemFormat::from_path(path))
    }

    /// Load and assemble the problem saved in `path`.
    pub fn load_problem(path: impl AsRef<Path>) -> Result<CcpProblem> {
        Self::load(path)?.to_problem()
    }
}

/// Names the field an IO error happened in (`field: error`).
pub(super) fn at(field: impl Into<String>) -> impl Fn(std::io::Error) -> std::io::Error {
    let field = field.into();
    move |e| std::io::Error::new(e.kind(), format!("`{field}`: {e}"))
}

/// A stored dense block: `matrix` must hold `ndof^2` values (row-major).
fn dense_block(ndof: usize, matrix: &[f64]) -> Result<MassOperator> {
    if ndof.checked_mul(ndof) != Some(matrix.len()) {
        return Err(ChronoError::invalid(
            "dense mass matrix.len()",
            matrix.len(),
            format!("must be ndof^2 with ndof = {ndof}"),
        ));
    }
    let m = nalgebra::DMatrix::from_row_slice(ndof, ndof, matrix);
    let op = super::coupled::DenseMass::new(m)?;
    MassOperator::coupled(std::sync::Arc::new(op))
}

/// Structural checks of one stored group, so that assembly never indexes out of bounds.
fn check_group(name: &str, g: &GroupData) -> Result<()> {
    let bad = |field: &str, value: usize, reason: String| {
        Err(ChronoError::invalid(
            format!("groups.{name}.{field}"),
            value,
            reason,
        ))
    };
    let n = g.b.len();
    if g.row_ptr.len() != n + 1 || g.row_ptr[0] != 0 {
        return bad(
            "row_ptr.len()",
            g.row_ptr.len(),
            format!("must be rows + 1 = {} and start at 0", n + 1),
        );
    }
    if g.row_ptr.windows(2).any(|w| w[0] > w[1]) || g.row_ptr[n] as usize != g.ent_block.len() {
        return bad(
            "row_ptr",
            n,
            "must be non-decreasing and end at the entry count".into(),
        );
    }
    if g.ent_coef.len() != g.ent_block.len() {
        return bad(
            "ent_coef.len()",
            g.ent_coef.len(),
            "must equal the entry count".into(),
        );
    }
    if g.ent_coef.windows(2).any(|w| w[0] > w[1])
        || g.ent_coef.first().is_some_and(|&c| c != 0)
        || g.ent_coef
            .last()
            .is_some_and(|&c| c as usize > g.coefs.len())
    {
        return bad(
            "ent_coef",
            g.coefs.len(),
            "must be non-decreasing offsets into coefs".into(),
        );
    }
    if g.eps.len() != n {
        return bad("eps.len()", g.eps.len(), format!("must equal rows = {n}"));
    }
    let (nlo, nmu) = match name {
        "box" => (n, 0),
        "friction" => (0, n / 3),
        "rolling" => (0, n / 2),
        "rolling_per_body" => (0, 3 * (n / PER_BODY_ROWS)),
        _ => (0, 0),
    };
    if g.lo.len() != nlo || g.hi.len() != nlo {
        return bad("lo.len()", g.lo.len(), format!("must be {nlo}"));
    }
    if g.mu.len() != nmu
        || (name == "friction" && !n.is_multiple_of(3))
        || (name == "rolling" && !n.is_multiple_of(6))
        || (name == "rolling_per_body" && !n.is_multiple_of(PER_BODY_ROWS))
    {
        return bad(
            "mu.len()",
            g.mu.len(),
            format!("must be {nmu} (whole cones)"),
        );
    }
    Ok(())
}

fn io_error(path: &Path, e: std::io::Error) -> ChronoError {
    ChronoError::invalid("problem file", path.display(), e.to_string())
}
