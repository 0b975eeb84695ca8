//! Running a case: writing it out, running it through the prism binary under bounds on time
//! and memory or in-process under `catch_unwind`, judging how it ended, and saving findings.

use super::{Case, Verdict};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// Bounds on one case.
#[derive(Clone, Copy, Debug)]
pub struct Limits {
    /// Bound on wall time in which a spawned prism gains no CPU time: catches a prism blocked
    /// without using the CPU (a deadlock, a read that never ends). A starved one still gains
    /// some CPU time (a 120 s bound on plain wall time flagged a 5 s case as a hang at nice 15
    /// under a load average of 10).
    pub timeout: Duration,
    /// CPU-time bound of a spawned prism (`prlimit --cpu`, SIGXCPU past it): catches a busy
    /// loop whatever the machine's load (a 20 s wall bound flagged an 8×32768 film at 1.9 s
    /// of CPU as a hang under a load average of 20).
    pub cpu_seconds: u64,
    /// Address-space limit of a spawned prism (`prlimit --as`), bytes.
    pub address_space: u64,
    /// `--max-memory` given to prism.
    pub max_memory: &'static str,
}

pub const LIMITS: Limits = Limits {
    timeout: Duration::from_secs(120),
    cpu_seconds: 20,
    address_space: 4 << 30,
    max_memory: "1GiB",
};

/// Writes `case` into `dir` (emptied first); returns the scene's path.
pub fn materialise(case: &Case, dir: &Path, repo: &Path) -> PathBuf {
    let _ = std::fs::remove_dir_all(dir);
    std::fs::create_dir_all(dir).unwrap();
    let fill = |t: &str| {
        t.replace("@REPO@", &repo.display().to_string())
            .replace("@CASE@", &dir.display().to_string())
    };
    let scene = dir.join("scene.ron");
    std::fs::write(&scene, fill(&case.scene)).unwrap();
    if let Some((name, bytes)) = &case.file {
        std::fs::write(dir.join(name), bytes).unwrap();
    }
    scene
}

fn args(scene: &Path, dir: &Path, limits: &Limits) -> Vec<String> {
    let s = |p: PathBuf| p.display().to_string();
    vec![
        "render".into(),
        scene.display().to_string(),
        "-o".into(),
        s(dir.join("out.exr")),
        "--preview".into(),
        s(dir.join("out.png")),
        "--spp".into(),
        "1".into(),
        "--threads".into(),
        "1".into(),
        "--max-memory".into(),
        limits.max_memory.into(),
        "-q".into(),
    ]
}

/// Runs the prism binary `bin` on the case in `dir`, under the limits.
pub fn run_binary(bin: &Path, scene: &Path, dir: &Path, limits: &Limits) -> (Verdict, String) {
    let before = present(dir);
    spawn_judged(bin, args(scene, dir, limits), limits, &|c, err| {
        promise(c, dir, Some(err), &before)
    })
}

/// Runs `bin` with `args` under the limits; `judge(code, stderr)` says what an exit 0 or 2
/// broke (None: kept).
fn spawn_judged(
    bin: &Path,
    args: Vec<String>,
    limits: &Limits,
    judge: &dyn Fn(i32, &str) -> Option<String>,
) -> (Verdict, String) {
    let mut child = Command::new("prlimit")
        .arg(format!("--as={}", limits.address_space))
        // Soft limit first: SIGXCPU (below), a second later the hard limit's SIGKILL.
        .arg(format!(
            "--cpu={}:{}",
            limits.cpu_seconds,
            limits.cpu_seconds + 1
        ))
        .arg("--")
        .arg(bin)
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("prlimit and prism run");
    let mut stderr = child.stderr.take().unwrap();
    let reader = std::thread::spawn(move || {
        let mut s = String::new();
        use std::io::Read;
        let _ = stderr.read_to_string(&mut s);
        s
    });
    let (mut cpu, mut progress) = (0, Instant::now());
    let status = loop {
        if let Some(st) = child.try_wait().unwrap() {
            break Some(st);
        }
        let now = cpu_ticks(child.id()).unwrap_or(cpu);
        if now > cpu {
            (cpu, progress) = (now, Instant::now());
        }
        if progress.elapsed() > limits.timeout {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(Duration::from_millis(2));
    };
    let err = reader.join().unwrap_or_default();
    let v = match status {
        None => Verdict::Hang,
        Some(st) => match st.code() {
            _ if err.contains("panicked") => Verdict::Panic(tail(&err)),
            Some(c @ (0 | 2)) => match judge(c, &err) {
                Some(broken) => Verdict::Broken(broken),
                None => Verdict::Ok(c),
            },
            Some(101) => Verdict::Panic(tail(&err)),
            Some(c) => Verdict::WrongExit(c, tail(&err)),
            None => {
                use std::os::unix::process::ExitStatusExt;
                match st.signal() {
                    Some(libc::SIGXCPU) => Verdict::Hang,
                    s => Verdict::Signal(format!("signal {s:?}: {}", tail(&err))),
                }
            }
        },
    };
    (v, err)
}

/// `args` after the program name, as `prism::cli::run` takes them.
pub fn with_program(args: Vec<String>) -> Vec<String> {
    let mut a = vec!["prism".to_string()];
    a.extend(args);
    a
}

/// None if the first `error:` line of `stderr` (where captured) starts with a file's path
/// (every path of a case is absolute), else what broke.
pub fn names_a_file(stderr: Option<&str>) -> Option<String> {
    let err = stderr?;
    let named = err
        .lines()
        .find_map(|l| l.strip_prefix("error: "))
        .is_some_and(|m| m.starts_with('/'));
    (!named).then(|| format!("exit 2 without a message naming a file: {}", tail(err)))
}

/// Writes `case` into `dir` and runs it through the binary (a dataset case through `prism
/// dataset`, its folder's FIFOs real), under the limits.
pub fn run_case_binary(
    bin: &Path,
    case: &Case,
    dir: &Path,
    repo: &Path,
    limits: &Limits,
) -> (Verdict, String) {
    // The CPU bound grows with the samples the case asks for (engine/work.rs).
    let limits = &super::work::limits_for(case, limits);
    let Some(d) = &case.dataset else {
        let scene = materialise(case, dir, repo);
        return run_binary(bin, &scene, dir, limits);
    };
    super::dataset::materialise(case, d, dir, repo, true);
    let before = super::dataset::snapshot(&dir.join("out"));
    let a = super::dataset::args(dir, &d.flags);
    spawn_judged(bin, a, limits, &|c, err| {
        super::dataset::promise(c, dir, &d.flags, Some(err), &before)
    })
}

/// Writes `case` into `dir` and runs it in-process (`prism::cli::run`, panics caught).
pub fn run_case_in_process(case: &Case, dir: &Path, repo: &Path, limits: &Limits) -> Verdict {
    let Some(d) = &case.dataset else {
        let scene = materialise(case, dir, repo);
        return run_in_process(&scene, dir, limits);
    };
    super::dataset::materialise(case, d, dir, repo, false);
    let before = super::dataset::snapshot(&dir.join("out"));
    let a = with_program(super::dataset::args(dir, &d.flags));
    in_process_judged(a, &|c| {
        super::dataset::promise(c, dir, &d.flags, None, &before)
    })
}

/// The outputs a case's run writes (`args`): the EXR, its sidecar and the preview.
pub const OUTPUTS: [&str; 3] = ["out.exr", "out.json", "out.png"];

/// What exit code `code` promises, checked on the case's directory (and on stderr, where it was
/// captured): exit 2 leaves no output file behind and its message names a file (every path of a
/// case is absolute, so the message starts with one); exit 0 wrote the EXR and the sidecar, and
/// every channel of the EXR holds only finite values. None if kept, else what broke.
pub fn promise(code: i32, dir: &Path, stderr: Option<&str>, before: &[&str]) -> Option<String> {
    if code == 2 {
        let left: Vec<&str> = present(dir)
            .into_iter()
            .filter(|n| !before.contains(n))
            .collect();
        if !left.is_empty() {
            return Some(format!("exit 2 left {left:?} behind"));
        }
        return names_a_file(stderr);
    }
    for n in &OUTPUTS[..2] {
        if !dir.join(n).is_file() {
            return Some(format!("exit 0 without {n}"));
        }
    }
    non_finite(&dir.join("out.exr"))
}

/// The outputs present in `dir` (before a run: a case's own input file may bear such a name).
pub fn present(dir: &Path) -> Vec<&'static str> {
    OUTPUTS
        .into_iter()
        .filter(|n| std::fs::symlink_metadata(dir.join(n)).is_ok())
        .collect()
}

/// The first channel of an EXR holding a NaN or an infinity (but the documented +inf of
/// `depth` and `distance` on the background), or a failure to read it.
pub fn non_finite(exr: &Path) -> Option<String> {
    use exr::prelude::FlatSamples;
    let img = match exr::prelude::read_all_flat_layers_from_file(exr) {
        Ok(i) => i,
        Err(e) => return Some(format!("exit 0 with an unreadable EXR: {e}")),
    };
    for layer in &img.layer_data {
        for ch in &layer.channel_data.list {
            // `depth` and `distance` are +inf where no surface is hit (scenes/README.md, AOVs).
            let name = ch.name.to_string();
            let far = name.starts_with("depth.") || name.starts_with("distance.");
            let ok = |x: f32| x.is_finite() || (far && x == f32::INFINITY);
            let bad = match &ch.sample_data {
                FlatSamples::F16(v) => v.iter().position(|x| !ok(x.to_f32())),
                FlatSamples::F32(v) => v.iter().position(|&x| !ok(x)),
                FlatSamples::U32(_) => None,
            };
            if let Some(i) = bad {
                return Some(format!(
                    "exit 0 with a non-finite value in channel {} (sample {i})",
                    ch.name
                ));
            }
        }
    }
    None
}

fn tail(s: &str) -> String {
    let lines: Vec<&str> = s.lines().collect();
    lines[lines.len().saturating_sub(6)..].join("\n")
}

static PANIC: Mutex<Option<String>> = Mutex::new(None);

/// Makes in-process panics quiet and records the last message (call once).
pub fn install_panic_hook() {
    std::panic::set_hook(Box::new(|info| {
        let msg = format!("{info}");
        if info.location().is_some_and(|l| l.file().contains("fuzz")) {
            eprintln!("the fuzzer itself panicked: {msg}");
        }
        *PANIC.lock().unwrap_or_else(|e| e.into_inner()) = Some(msg);
    }));
}

/// User plus system CPU time of process `pid` (all its threads), in clock ticks: fields 14 and
/// 15 of /proc/PID/stat, counted after the parenthesised command name (which may hold spaces).
fn cpu_ticks(pid: u32) -> Option<u64> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    let mut f = stat.rsplit_once(')')?.1.split_whitespace().skip(11);
    Some(f.next()?.parse::<u64>().ok()? + f.next()?.parse::<u64>().ok()?)
}

/// Runs the case in `dir` through `prism::cli::run` in this process, catching panics. Hangs
/// and memory are not bounded here (the binary runs are for those).
pub fn run_in_process(scene: &Path, dir: &Path, limits: &Limits) -> Verdict {
    let before = present(dir);
    let a = with_program(args(scene, dir, limits));
    in_process_judged(a, &|c| promise(c, dir, None, &before))
}

fn in_process_judged(a: Vec<String>, judge: &dyn Fn(i32) -> Option<String>) -> Verdict {
    match std::panic::catch_unwind(|| prism::cli::run(a)) {
        Ok(c @ (0 | 2)) => match judge(c) {
            Some(broken) => Verdict::Broken(broken),
            None => Verdict::Ok(c),
        },
        Ok(c) => Verdict::WrongExit(c, String::new()),
        Err(_) => Verdict::Panic(
            PANIC
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .take()
                .unwrap_or_default(),
        ),
    }
}

/// A regression case of tests/fuzz_corpus/: a directory with `scene.ron` (placeholders as
/// above) and at most one other file, the input it reads.
pub fn load_corpus_case(dir: &Path) -> Case {
    let scene = std::fs::read_to_string(dir.join("scene.ron")).unwrap();
    // A dataset case: `case.json` holds the config, the priming pair, the state and the flags.
    if let Ok(j) = std::fs::read_to_string(dir.join("case.json")) {
        return Case {
            index: 0,
            what: dir.display().to_string(),
            scene,
            file: None,
            dataset: Some(serde_json::from_str(&j).expect("a dataset case's case.json")),
        };
    }
    let mut file = None;
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        let name = p.file_name().unwrap().to_string_lossy().into_owned();
        if !matches!(
            name.as_str(),
            "scene.ron" | "README" | "expect" | "case.json"
        ) {
            file = Some((name, std::fs::read(&p).unwrap()));
        }
    }
    Case {
        index: 0,
        what: dir.display().to_string(),
        scene,
        file,
        dataset: None,
    }
}

/// Saves a failing case as a corpus-style directory under `out`.
pub fn save_finding(case: &Case, verdict: &Verdict, stderr: &str, out: &Path) -> PathBuf {
    let d = out.join(format!("{}-{}", verdict.label(), case.index));
    let _ = std::fs::create_dir_all(&d);
    std::fs::write(d.join("scene.ron"), &case.scene).unwrap();
    if let Some((n, b)) = &case.file {
        std::fs::write(d.join(n), b).unwrap();
    }
    if let Some(ds) = &case.dataset {
        let j = serde_json::to_string_pretty(ds).expect("cases serialise");
        std::fs::write(d.join("case.json"), j).unwrap();
    }
    std::fs::write(
        d.join("README"),
        format!("{}\n{verdict:?}\n{stderr}\n", case.what),
    )
    .unwrap();
    d
}
