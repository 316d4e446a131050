//! Fuzzed problem files: generated mutations of a saved problem, in both encodings, never
//! make reading or assembling panic, and every rejected file is an error that names the
//! field (its path in the JSON document or in the binary layout).

use proptest::prelude::*;

use super::tests::sample;
use super::{CcpProblem, ProblemFile};
use crate::error::ChronoError;
use crate::testing::json_mutation::{MUTATIONS, error_names_path, mutate, paths};

fn saved() -> ProblemFile {
    let (prob, ..) = sample();
    ProblemFile::from_problem(&prob, "fuzz")
}

fn binary(file: &ProblemFile) -> Vec<u8> {
    let path = std::env::temp_dir().join(format!(
        "chrono-core-fuzz-{}-{:?}.bin",
        std::process::id(),
        std::thread::current().id()
    ));
    file.save(&path, super::ProblemFormat::Binary).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    std::fs::remove_file(&path).ok();
    bytes
}

/// Assembling a file that was read: a problem, or an error naming a field (in backticks,
/// or the field of an [`ChronoError::InvalidParameter`]).
fn assemble(file: &ProblemFile) -> Result<Option<CcpProblem>, TestCaseError> {
    match file.to_problem() {
        Ok(p) => Ok(Some(p)),
        Err(ChronoError::InvalidParameter { field, .. }) => {
            prop_assert!(!field.is_empty(), "an assembly error names no field");
            Ok(None)
        }
        Err(e) => {
            let msg = e.to_string();
            prop_assert!(
                msg.contains('`'),
                "the assembly error names no field: {msg}"
            );
            Ok(None)
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, failure_persistence: None, ..ProptestConfig::default() })]

    /// A mutated JSON member: reading names the member (its key or an enclosing one), or
    /// the file reads and assembling names the field.
    #[test]
    fn mutated_json_file_never_panics(index in 0usize..100_000, mutation in 0usize..10) {
        let mut root = serde_json::to_value(saved()).unwrap();
        let all = paths(&root);
        let path = &all[index % all.len()];
        let m = MUTATIONS[mutation % MUTATIONS.len()];
        if mutate(&mut root, path, m) {
            let text = serde_json::to_vec(&root).unwrap();
            match ProblemFile::from_bytes(&text) {
                Err(e) => {
                    let msg = e.to_string();
                    prop_assert!(error_names_path(&msg, path, m), "{m:?} at {path:?}: {msg}");
                }
                Ok(file) => {
                    assemble(&file)?;
                }
            }
        }
    }

    /// Bytes of a binary file overwritten, cut or repeated: an error naming the field being
    /// read, or a file whose assembly is a problem or an error naming a field.
    #[test]
    fn corrupted_binary_file_never_panics(
        at in 0usize..100_000,
        len in 1usize..16,
        byte in any::<u8>(),
        how in 0usize..3,
    ) {
        let mut bytes = binary(&saved());
        let at = 8 + at % (bytes.len() - 8);
        let end = (at + len).min(bytes.len());
        match how {
            0 => bytes[at..end].fill(byte),
            1 => bytes.truncate(at),
            _ => {
                let chunk = bytes[at..end].to_vec();
                bytes.splice(at..at, chunk);
            }
        }
        match ProblemFile::from_bytes(&bytes) {
            Err(e) => {
                let msg = e.to_string();
                prop_assert!(msg.contains('`'), "names no field: {msg}");
            }
            Ok(file) => {
                assemble(&file)?;
            }
        }
    }
}

/// The unmutated file reads and assembles in both encodings, bit for bit.
#[test]
fn unmutated_files_round_trip() {
    let file = saved();
    let (prob, ..) = sample();
    for bytes in [serde_json::to_vec(&file).unwrap(), binary(&file)] {
        let back = ProblemFile::from_bytes(&bytes).unwrap();
        assert_eq!(back, file);
        let q = back.to_problem().unwrap();
        assert_eq!(q.r(), prob.r());
    }
}

/// A cut binary file names the field it stopped in.
#[test]
fn truncated_binary_names_the_field() {
    let bytes = binary(&saved());
    let e = ProblemFile::from_bytes(&bytes[..bytes.len() - 3]).unwrap_err();
    assert!(e.to_string().contains("`k`"), "{e}");
    let e = ProblemFile::from_bytes(&[bytes.clone(), vec![0]].concat()).unwrap_err();
    assert!(e.to_string().contains("after the last field"), "{e}");
}
