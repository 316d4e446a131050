//! Suspension templates: [`double_wishbone`].

pub mod double_wishbone;

pub use double_wishbone::{DoubleWishbone, DoubleWishboneData, MassData};
