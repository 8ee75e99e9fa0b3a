//! The residual-traction operators against the paper's kernels.
//!
//! Eqs. (5)-(7) with the no-separation condition (9), `B_theta = -dB_r/dphi`,
//! in the scaled variables of model.md (`g = 2 mu B_r / ((kappa+1) p0)`):
//!
//!   p(theta) = (1/pi) PV int [ -g'(phi) K_pt(theta-phi) + g(phi) K_pr(theta-phi) ] dphi
//!   q(theta) = (1/pi) PV int [ -g'(phi) K_qt(theta-phi) + g(phi) K_qr(theta-phi) ] dphi
//!
//! `K_qt = K_pr = sin u cos u / (2 (1 - cos u))` is Cauchy-singular like
//! `1/u`. Its principal value is taken by subtracting `F(theta) cot(u/2)/2`,
//! whose principal value over a period is zero; what remains is smooth and
//! periodic, so the midpoint rule on nodes offset from `phi = theta`
//! converges spectrally.

use std::f64::consts::PI;

use shakedown::Operators;

fn k_pt(u: f64) -> f64 {
    0.5 * u.cos() + 1.0
}
fn k_singular(u: f64) -> f64 {
    u.sin() * u.cos() / (2.0 * (1.0 - u.cos()))
}
fn k_qr(u: f64) -> f64 {
    -0.5 * u.cos()
}

/// `(1/pi) PV int_0^{2pi} [a(phi) K_regular(theta-phi) + b(phi) K_singular(theta-phi)] dphi`.
fn pv_integral(
    theta: f64,
    a: impl Fn(f64) -> f64,
    regular: impl Fn(f64) -> f64,
    b: impl Fn(f64) -> f64,
) -> f64 {
    let m = 4000;
    let h = 2.0 * PI / m as f64;
    let b_theta = b(theta);
    let mut sum = 0.0;
    for i in 0..m {
        let phi = theta + (i as f64 + 0.5) * h;
        let u = theta - phi;
        let cot_half = (u / 2.0).cos() / (u / 2.0).sin();
        sum += a(phi) * regular(u) + b(phi) * k_singular(u) - b_theta * 0.5 * cot_half;
    }
    sum * h / PI
}

#[test]
fn operators_match_principal_value_quadrature_of_the_kernels() {
    let n = 64;
    let ops = Operators::new(n);
    for (harmonic, offset) in [(1.0, 0.0), (1.0, 0.7), (2.0, 0.3), (3.0, -1.1), (7.0, 0.5)] {
        let g = move |phi: f64| (harmonic * phi + offset).cos();
        let dg = move |phi: f64| -harmonic * (harmonic * phi + offset).sin();
        let nodal: Vec<f64> = (0..n).map(|j| g(2.0 * PI * j as f64 / n as f64)).collect();
        let p = ops.residual_pressure(&nodal);
        let q = ops.residual_shear(&nodal);
        for j in (0..n).step_by(5) {
            let theta = 2.0 * PI * j as f64 / n as f64;
            // Pressure: B_theta with K_pt, B_r with the singular K_pr.
            let p_quad = pv_integral(theta, |phi| -dg(phi), k_pt, g);
            // Shear: B_theta with the singular K_qt, B_r with K_qr.
            let q_quad = pv_integral(theta, g, k_qr, |phi| -dg(phi));
            assert!(
                (p[j] - p_quad).abs() < 1e-6,
                "H: n = {harmonic}, theta = {theta}: matrix {} vs quadrature {p_quad}",
                p[j]
            );
            assert!(
                (q[j] - q_quad).abs() < 1e-6,
                "|D|: n = {harmonic}, theta = {theta}: matrix {} vs quadrature {q_quad}",
                q[j]
            );
        }
    }
}

#[test]
fn residual_tractions_carry_no_net_force_or_moment_and_store_positive_energy() {
    let n = 64;
    let ops = Operators::new(n);
    let g: Vec<f64> = (0..n)
        .map(|j| {
            let t = 2.0 * PI * j as f64 / n as f64;
            0.3 + (t).cos() - 0.4 * (3.0 * t).sin() + 0.1 * (5.0 * t + 1.0).cos()
        })
        .collect();
    let p = ops.residual_pressure(&g);
    let q = ops.residual_shear(&g);
    let theta = |j: usize| 2.0 * PI * j as f64 / n as f64;
    // Net force of the residual field: int (p n + q t) dtheta with the
    // outward normal n = (cos, sin) and tangent t = (-sin, cos).
    let fx: f64 = (0..n)
        .map(|j| p[j] * theta(j).cos() - q[j] * theta(j).sin())
        .sum();
    let fy: f64 = (0..n)
        .map(|j| p[j] * theta(j).sin() + q[j] * theta(j).cos())
        .sum();
    let moment: f64 = q.iter().sum();
    assert!(fx.abs() < 1e-9 && fy.abs() < 1e-9, "force ({fx}, {fy})");
    assert!(moment.abs() < 1e-9, "moment {moment}");
    let energy: f64 = -0.5 * q.iter().zip(&g).map(|(q, g)| q * g).sum::<f64>();
    assert!(energy > 0.0);
}

#[test]
fn slip_cos_theta_raises_the_pressure_near_plus_half_pi() {
    let n = 128;
    let ops = Operators::new(n);
    let g: Vec<f64> = (0..n)
        .map(|j| (2.0 * PI * j as f64 / n as f64).cos())
        .collect();
    let p = ops.residual_pressure(&g);
    let peak = (0..n).max_by(|&a, &b| p[a].total_cmp(&p[b])).unwrap();
    assert_eq!(peak, n / 4, "pressure peaks at theta = pi/2");
}
