use shakedown::*;
fn main() {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let (l, phi, init) = (
        a[0].parse::<f64>().unwrap(),
        a[1].parse::<f64>().unwrap() * std::f64::consts::PI,
        Initial::parse(&a[2]).unwrap(),
    );
    for &(n, st) in &[(128, 400), (256, 400), (128, 800), (256, 800)] {
        let mut row = format!("N={n} steps={st}:");
        for b in [0, 1, 2, 3, 4] {
            let mut o = StepOptions::default();
            o.stick_bisections = b;
            let t = std::time::Instant::now();
            let mut s = Stepper::new(
                Material::paper(),
                Discretisation::new(n, st).unwrap(),
                &init,
                Cycle::paper(l, phi).unwrap(),
                o,
            );
            let r = s.run_to_steady().unwrap();
            row += &format!(
                " b{b}: {:.6} ({:?} {}ms)",
                r.dissipation,
                r.state.as_str().chars().take(6).collect::<String>(),
                t.elapsed().as_millis()
            );
        }
        println!("{row}");
    }
}
