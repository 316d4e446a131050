mod common;
use chrono_ccp::*;
use common::box_stack_ratio;
#[test]
fn explore() {
    for ratio in [1.0, 3.0, 1.0/3.0] {
    let problem = box_stack_ratio(5, ratio, 0.5, 0.01);
    for (name, mut s) in [
        ("psor", Box::new(Psor::new(SolverSettings{tolerance:1e-6,max_iterations:200000,record_history:true})) as Box<dyn CcpSolver>),
        ("psor sym", Box::new(Psor::new(SolverSettings{tolerance:1e-6,max_iterations:200000,record_history:true}).with_symmetric(true))),
        ("apgd", Box::new(Apgd::new(SolverSettings{tolerance:1e-6,max_iterations:200000,record_history:true}))),
    ] {
        let mut g = vec![0.0; problem.n_rows()];
        let st = s.solve(&problem, &mut g);
        let h = &st.history;
        let pick: Vec<_> = [1usize,10,100,1000,10000,100000].iter().filter(|&&i| i <= h.len()).map(|&i| (i, h[i-1].residual)).collect();
        eprintln!("ratio {ratio} {name}: it {} res {:.3e} conv {} {:?}", st.iterations, st.residual, st.converged, pick);
    }
    }
}
