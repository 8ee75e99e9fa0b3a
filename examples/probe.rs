use shakedown::*;
fn main() {
    let args: Vec<f64> = std::env::args()
        .skip(1)
        .map(|a| a.parse().unwrap())
        .collect();
    let (lambda, phi) = (args[0], args[1] * std::f64::consts::PI);
    let nodes = args.get(2).copied().unwrap_or(128.0) as usize;
    let steps = args.get(3).copied().unwrap_or(400.0) as usize;
    let m = Material::paper();
    let d = Discretisation::new(nodes, steps).unwrap();
    let c = Cycle::paper(lambda, phi).unwrap();
    for init in Initial::paper_set()
        .iter()
        .take(args.get(4).copied().unwrap_or(1.0) as usize)
    {
        let t = std::time::Instant::now();
        let mut s = Stepper::new(m, d, init, c, StepOptions::default());
        let r = s.run_to_steady();
        let hist: Vec<String> = s
            .history()
            .iter()
            .map(|h| format!("{:.5}", h.dissipation))
            .collect();
        println!(
            "{init} {:?} {:?} hist[{}]={:?}",
            r.as_ref().map(|r| (
                r.state,
                r.dissipation,
                r.cycles,
                r.rotation_per_cycle,
                r.approach
            )),
            t.elapsed(),
            hist.len(),
            &hist[hist.len().saturating_sub(4)..]
        );
    }
}
