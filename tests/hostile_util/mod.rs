//! Helpers of the hostile-input tests (tests/hostile.rs, tests/hostile_dataset.rs): the binary
//! run with a wall bound, and what its exit and messages must be.
#![allow(dead_code)]

#[path = "../scratch/mod.rs"]
pub mod scratch;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

pub fn prism() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_prism"));
    c.stdin(Stdio::null());
    c
}

pub fn workdir(name: &str) -> scratch::Scratch {
    scratch::scratch("hostile", name)
}

pub const SCENE: &str = r#"(film: (width: 8, height: 6), sampler: (spp: 1),
 camera: (fov: 40, to_world: [LookAt(origin: (0, 0, 5), target: (0, 0, 0), up: (0, 1, 0))]),
 materials: {"m": Diffuse()}, shapes: [(shape: Sphere(radius: 1), material: "m", name: "ball")],
 emitters: [Constant(radiance: Named("D65"))])"#;

/// Runs with a wall bound (a FIFO read would block forever): the output, or a panic naming
/// the case if it ran past `secs`.
pub fn run(mut c: Command, secs: u64, what: &str) -> Output {
    let mut child = c
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let t = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if t.elapsed() > Duration::from_secs(secs) {
            let _ = child.kill();
            let _ = child.wait();
            panic!("{what}: still running after {secs} s (a hang)");
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    child.wait_with_output().unwrap()
}

pub fn code(o: &Output) -> Option<i32> {
    o.status.code()
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Exit 2 with each of `want` in the message.
pub fn refused(o: &Output, what: &str, want: &[&str]) {
    let e = stderr(o);
    assert_eq!(code(o), Some(2), "{what}: exit {:?}\n{e}", code(o));
    assert!(e.contains("hint:"), "{what}: no hint in\n{e}");
    for w in want {
        assert!(e.contains(w), "{what}: no `{w}` in\n{e}");
    }
}

pub fn render(dir: &Path, scene: &str, out: &str, extra: &[&str]) -> Output {
    let mut c = prism();
    c.current_dir(dir)
        .args(["render", scene, "-o", out, "-q"])
        .args(extra);
    run(c, 60, &format!("render {scene} -o {out}"))
}

pub fn mkfifo(p: &Path) {
    assert!(Command::new("mkfifo").arg(p).status().unwrap().success());
}

pub fn dataset(dir: &Path, cfg: &str, out: &str, extra: &[&str]) -> Output {
    let mut c = prism();
    c.current_dir(dir)
        .args(["dataset", cfg, "-o", out, "--quiet"])
        .args(extra)
        .env_remove("SLURM_ARRAY_TASK_ID")
        .env_remove("SLURM_ARRAY_TASK_COUNT")
        .env_remove("JOB_COMPLETION_INDEX");
    run(c, 120, &format!("dataset {cfg} -o {out}"))
}

pub const DATASET: &str =
    "(scene: \"s.ron\", frames: 2, seed: 1, outputs: (spp: 1, resolution: (8, 6)))";

pub fn walk(d: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(d).into_iter().flatten().flatten() {
        let p = e.path();
        if p.is_dir() {
            out.extend(walk(&p));
        } else {
            out.push(p);
        }
    }
    out
}
