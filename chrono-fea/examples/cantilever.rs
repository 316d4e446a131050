//! A steel cantilever (1 m, 2 cm x 2 cm section, 16 ANCF cable elements) under a small
//! dead tip load: the static tip deflection against Euler–Bernoulli, `P L^3 / (3 E I)`.
//!
//! `cargo run --release -p chrono-fea --example cantilever`

use chrono_fea::{NodeId, StaticSettings, cable_cantilever, solve_static};
use nalgebra::Vector3;

fn main() -> Result<(), chrono_fea::FeaError> {
    let (length, young, width, height, n) = (1.0, 2.0e11, 0.02, 0.02, 16);
    let mut mesh = cable_cantilever(n, length, young, 7850.0, width, height)?;
    let load = -100.0; // N, along Z
    mesh.set_force(NodeId(n), Vector3::new(0.0, 0.0, load))?;
    let report = solve_static(&mut mesh, &StaticSettings::default())?;
    let tip = mesh.node(NodeId(n))?.displacement().z;
    let ei = young * width * height.powi(3) / 12.0;
    let exact = load * length.powi(3) / (3.0 * ei);
    println!("tip deflection     {tip:.6e} m");
    println!("P L^3 / (3 E I)    {exact:.6e} m");
    println!("relative error     {:.2e}", (tip / exact - 1.0).abs());
    println!("Newton iterations  {}", report.total_iterations());
    Ok(())
}
