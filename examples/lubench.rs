use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::lu::partial_pivoting::factor::{
    lu_in_place, lu_in_place_scratch, PartialPivLuParams,
};
use faer::{Mat, Par};
fn main() {
    for &k in &[20usize, 43, 80, 120] {
        let a = Mat::<f64>::from_fn(k, k, |i, j| {
            if i == j {
                10.0
            } else {
                ((i * 7 + j * 13) % 17) as f64 / 17.0
            }
        });
        let mut perm = vec![0usize; k];
        let mut inv = vec![0usize; k];
        let mut mem = MemBuffer::new(lu_in_place_scratch::<usize, f64>(
            k,
            k,
            Par::Seq,
            Default::default(),
        ));
        for (name, rt, bs) in [
            ("default", 0usize, 0usize),
            ("rt=16", 16, 16),
            ("rt=256", 256, 64),
            ("rt=8", 8, 8),
        ] {
            let reps = 20000;
            let t = std::time::Instant::now();
            for _ in 0..reps {
                let mut m = a.clone();
                let params = if rt == 0 {
                    Default::default()
                } else {
                    let mut p: PartialPivLuParams = faer::Auto::<f64>::auto();
                    p.recursion_threshold = rt;
                    p.block_size = bs;
                    p.into()
                };
                lu_in_place(
                    m.as_mut(),
                    &mut perm,
                    &mut inv,
                    Par::Seq,
                    MemStack::new(&mut mem),
                    params,
                );
                std::hint::black_box(&m);
            }
            println!(
                "k={k} {name}: {:.2} us",
                t.elapsed().as_secs_f64() / reps as f64 * 1e6
            );
        }
    }
}
