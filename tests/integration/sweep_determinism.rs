//! Sweep output must not depend on the number of threads.

use std::f64::consts::PI;
use std::process::Command;

fn sweep(threads: usize) -> Vec<u8> {
    let out = Command::new(env!("CARGO_BIN_EXE_shakedown"))
        .args([
            "sweep",
            "--lambda",
            "4.8,5.5,7",
            "--phi",
            "0,pi/2",
            "--initial",
            "OA,7,-7,-5,7",
            "--nodes",
            "64",
            "--steps",
            "200",
        ])
        .env("RAYON_NUM_THREADS", threads.to_string())
        .output()
        .expect("the binary runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    out.stdout
}

#[test]
fn same_bytes_whatever_the_thread_count() {
    let one = sweep(1);
    let two = sweep(2);
    let three = sweep(3);
    assert_eq!(one, two);
    assert_eq!(one, three);
    let text = String::from_utf8(one).unwrap();
    // The `# key = value` header says what made the file.
    assert!(text.starts_with("# shakedown = "));
    assert!(text.contains("\n# initial = OA 7,-7 -5,7\n"), "{text}");
    let mut lines = text.lines().skip_while(|l| l.starts_with('#'));
    assert_eq!(
        lines.next(),
        Some("lambda,phi,initial,state,dissipation,cycles,rotation_per_cycle")
    );
    let rows: Vec<&str> = lines.collect();
    assert_eq!(rows.len(), 3 * 2 * 3);
    // Row order: lambda outermost, then phi, then the initial paths.
    assert!(rows[0].starts_with("4.8,0,\"OA\","));
    assert!(rows[3].starts_with(&format!("4.8,{},\"OA\",", PI / 2.0)));
    assert!(rows[6].starts_with("5.5,0,\"OA\","));
}
