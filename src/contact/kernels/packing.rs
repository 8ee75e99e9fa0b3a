//! Unpacking of the FFT's responses ([`crate::contact::operators`]) into
//! the exact increment's arrays: a plain loop the compiler vectorises (the
//! same loops in `pulp`'s dispatch gained 3.8 % of the instructions of the
//! `N = 1024` run, under the 5 % a specialisation must gain; see
//! `benches/README.md`).

use rustfft::num_complex::Complex64;

/// The negated real parts of the bins `|D| g' + i H g'` into `hq`
/// (`-|D| g'`) and their imaginary parts into `hp` (`H g'`), and the
/// totals `tp = (ux epx + uy epy) + hp`, `tq = (ux eqx + uy eqy) + hq`
/// ([`super::combine_plus`]) in the same pass, in the same operations: the
/// bits of the separate passes, with the responses read once (the totals'
/// own pass was some 4 % of a run at `N = 1024`).
pub(in crate::contact) fn from_complex_totals(
    bins: &[Complex64],
    h: [&mut [f64]; 2],
    t: [&mut [f64]; 2],
    u: (f64, f64),
    elastic: [&[f64]; 4],
) {
    let [hp, hq] = h;
    let [tp, tq] = t;
    let (ux, uy) = u;
    let [epx, epy, eqx, eqy] = elastic;
    let n = hp.len();
    let (hq, tp, tq) = (&mut hq[..n], &mut tp[..n], &mut tq[..n]);
    let (epx, epy, eqx, eqy) = (&epx[..n], &epy[..n], &eqx[..n], &eqy[..n]);
    for (j, z) in bins[..n].iter().enumerate() {
        let q = -z.re;
        let p = z.im;
        hp[j] = p;
        hq[j] = q;
        tp[j] = (ux * epx[j] + uy * epy[j]) + p;
        tq[j] = (ux * eqx[j] + uy * eqy[j]) + q;
    }
}
