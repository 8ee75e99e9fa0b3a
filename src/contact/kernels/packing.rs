//! Packing of slip vectors into the FFT of [`crate::contact::operators`]
//! and of its responses out of it, vectorised by the compiler in each
//! instruction set's copy (see [`super`]).

wide! {
    /// `pairs = (x_j, 0)` for every `j`: a real vector as complex numbers
    /// (`{ re, im }` pairs) for the FFT of [`crate::contact::operators`].
    fn to_complex<'a>(pairs: &'a mut [f64], x: &'a [f64]) -> () {
        for (pair, &x) in pairs.chunks_exact_mut(2).zip(x) {
            pair[0] = x;
            pair[1] = 0.0;
        }
    }
}

wide! {
    /// `x *= s` elementwise.
    fn scale<'a>(x: &'a mut [f64], s: &'a [f64]) -> () {
        for (x, &s) in x.iter_mut().zip(s) {
            *x *= s;
        }
    }
}

wide! {
    /// The real parts of complex numbers (`{ re, im }` pairs) into `re`,
    /// and the imaginary parts into `im`.
    fn from_complex<'a>(pairs: &'a [f64], re: &'a mut [f64], im: &'a mut [f64]) -> () {
        for ((pair, re), im) in pairs.chunks_exact(2).zip(re.iter_mut()).zip(im.iter_mut()) {
            *re = pair[0];
            *im = pair[1];
        }
    }
}

wide! {
    /// [`from_complex`] negated into `hq` (`-|D| g'`) and `hp` (`H g'`),
    /// and the totals `tp = (ux epx + uy epy) + hp`, `tq = (ux eqx + uy
    /// eqy) + hq` ([`combine_plus`]) in the same pass, in the same
    /// operations: the bits of the two passes, with the responses read
    /// once (the totals' own pass was some 4 % of a run at `N = 1024`).
    fn from_complex_totals<'a>(
        pairs: &'a [f64],
        h: [&'a mut [f64]; 2],
        t: [&'a mut [f64]; 2],
        u: (f64, f64),
        elastic: [&'a [f64]; 4],
    ) -> () {
        let [hp, hq] = h;
        let [tp, tq] = t;
        let (ux, uy) = u;
        let [epx, epy, eqx, eqy] = elastic;
        let n = hp.len();
        let (hq, tp, tq) = (&mut hq[..n], &mut tp[..n], &mut tq[..n]);
        let (epx, epy, eqx, eqy) = (&epx[..n], &epy[..n], &eqx[..n], &eqy[..n]);
        for (j, pair) in pairs[..2 * n].chunks_exact(2).enumerate() {
            let q = -pair[0];
            let p = pair[1];
            hp[j] = p;
            hq[j] = q;
            tp[j] = (ux * epx[j] + uy * epy[j]) + p;
            tq[j] = (ux * eqx[j] + uy * eqy[j]) + q;
        }
    }
}
