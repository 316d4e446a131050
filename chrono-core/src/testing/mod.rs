//! Test support shared by the crates' tests (feature `testing`, and this crate's own
//! tests): generated mutations of scene files for fuzzing their readers.

pub mod json_mutation;
