use shakedown::*;
fn main() {
    let args: Vec<f64> = std::env::args()
        .skip(1)
        .map(|a| a.parse().unwrap())
        .collect();
    let m = Material::paper();
    let d = Discretisation::new(args.get(2).copied().unwrap_or(128.0) as usize, 400).unwrap();
    let c = Cycle::paper(args[0], args[1] * std::f64::consts::PI).unwrap();
    let mut o = StepOptions::default();
    o.convergence.detect_asymptotic = false;
    o.convergence.max_cycles = 60;
    let mut s = Stepper::new(m, d, &Initial::Direct, c, o);
    let _ = s.run_to_steady();
    for h in s.history() {
        let n = h.slipping_nodes().iter().filter(|&&x| x).count();
        println!(
            "{} {:.6e} rot {:.3e} nodes {}",
            h.cycle, h.dissipation, h.rotation, n
        );
    }
}
