use shakedown::*;
fn main() {
    let args: Vec<f64> = std::env::args()
        .skip(1)
        .map(|a| a.parse().unwrap())
        .collect();
    let m = Material::paper();
    let d = Discretisation::new(128, 400).unwrap();
    let c = Cycle::paper(args[0], args[1] * std::f64::consts::PI).unwrap();
    let mut o = StepOptions::default();
    o.stick_bisections = args.get(2).copied().unwrap_or(3.0) as usize;
    let mut s = Stepper::new(m, d, &Initial::Direct, c, o);
    let (mut steps, mut sub, mut fact, mut slipn, mut it) = (0, 0, 0, 0usize, 0);
    let t = std::time::Instant::now();
    while matches!(s.status(), Status::Running) {
        let r = s.step().unwrap();
        steps += 1;
        sub += r.substeps;
        fact += r.factorisations;
        it += r.iterations;
        slipn += s
            .contact()
            .directions()
            .iter()
            .filter(|d| d.is_slipping())
            .count();
    }
    println!(
        "it {it} {:?} steps {steps} substeps {sub} factorisations {fact} mean|S| {:.1} {:?}",
        s.summary().unwrap().state,
        slipn as f64 / steps as f64,
        t.elapsed()
    );
}
