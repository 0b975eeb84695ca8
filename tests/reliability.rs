//! Reliability (issue 14): no input crashes prism or destroys a file. Regression tests for the
//! defects found by hand with hostile inputs; most run the `prism` binary on a tiny scene
//! (16×12 or smaller, 1-4 spp) so that the whole file takes seconds. docs/reliability.md
//! describes what each class of input gets.

mod scratch;
use glam::{Vec2, Vec3};
use prism::bsdf::{BsdfLike, Material};
use prism::interaction::SurfaceInteraction;
use prism::math::Frame;
use prism::spectrum::{WavelengthSampler, WavelengthSampling};
use prism::texture::{FloatTexture, Grid, TexFilter, UvMap, Wrap};
use std::path::{Path, PathBuf};
use std::process::Command;

fn material(cfg: &str) -> Material {
    let text = format!(
        "(film: (width: 2, height: 2), outputs: (bands: 0), materials: {{ \"m\": {cfg} }}, shapes: [(shape: Rectangle, material: \"m\")])"
    );
    let job = prism::load::load_str(&text, Path::new("inline.ron"))
        .unwrap_or_else(|e| panic!("{cfg}: {e}"));
    job.scene.materials[0].clone()
}

/// A 2×2 bitmap with one NaN texel: bilinear lookups anywhere near it are NaN.
fn nan_bitmap() -> FloatTexture {
    FloatTexture::Bitmap(Box::new(Grid {
        width: 2,
        height: 2,
        texels: vec![0.5, f32::NAN, 0.5, 0.5],
        wrap: Wrap::Repeat,
        wrap_v: Wrap::Repeat,
        filter: TexFilter::Bilinear,
        map: UvMap::IDENTITY,
        source: None,
    }))
}

/// Issue 14 item 1: a NaN opacity or blend weight (a NaN texel) made the mixture empty and
/// `Mixture::sample` indexed past its end (exit 101). Now such a weight counts as 0.
#[test]
fn nan_mask_opacity_and_blend_weight_do_not_panic() {
    let diffuse = material("Diffuse(reflectance: Constant(0.5))");
    let cases = [
        (
            "mask, NaN bitmap",
            Material::Mask {
                inner: Box::new(diffuse.clone()),
                opacity: nan_bitmap(),
            },
        ),
        (
            "mask, NaN constant",
            Material::Mask {
                inner: Box::new(diffuse.clone()),
                opacity: FloatTexture::Constant(f32::NAN),
            },
        ),
        (
            "blend, NaN bitmap",
            Material::Blend {
                a: Box::new(diffuse.clone()),
                b: Box::new(material("RoughConductor(alpha: 0.3)")),
                weight: nan_bitmap(),
            },
        ),
    ];
    let si = SurfaceInteraction {
        p: Vec3::ZERO,
        p_error: Vec3::ZERO,
        ng: Vec3::Z,
        frame: Frame::from_normal(Vec3::Z),
        uv: Vec2::new(0.5, 0.5),
        t: 1.0,
        shape: 0,
        prim: 0,
        time: 0.0,
        bary: glam::Vec2::ZERO,
    };
    let wl = WavelengthSampler::new(WavelengthSampling::Uniform, 360.0, 830.0).sample::<4>(0.37);
    let wi = Vec3::new(0.3, 0.1, 0.9).normalize();
    for (name, m) in &cases {
        let b = m.bsdf(&si, wi, &wl);
        for k in 0..16 {
            let uc = k as f32 / 16.0;
            if let Some(s) = b.sample(wi, uc, Vec2::new(0.3, uc)) {
                assert!(
                    s.weight.0.iter().all(|w| w.is_finite()),
                    "{name}: non-finite weight"
                );
            }
        }
        let f = b.eval(wi, Vec3::new(-0.2, 0.1, 0.97).normalize());
        assert!(f.0.iter().all(|v| v.is_finite()), "{name}: eval {f:?}");
    }
}

// ---- The binary: outputs that would destroy an input, late failures, exit codes. ----

fn prism() -> Command {
    Command::new(env!("CARGO_BIN_EXE_prism"))
}

fn workdir(name: &str) -> scratch::Scratch {
    scratch::scratch("rel", name)
}

const GOOD: &str = r#"(
    film: (width: 16, height: 12),
    sampler: (spp: 2),
    materials: { "grey": Diffuse(reflectance: Constant(0.5)) },
    shapes: [(shape: Sphere(center: (0, 0, 4)), material: "grey")],
    emitters: [Constant(radiance: Named("D65"))],
)"#;

/// The test data's 16×8 grey envmap, a PNG texture and a spectrum file, next to a scene that
/// reads all three; returns the scene's path.
fn scene_with_inputs(dir: &Path) -> PathBuf {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    std::fs::copy(data.join("envmap_grey_16x8.exr"), dir.join("sky.exr")).unwrap();
    image::RgbImage::from_pixel(2, 2, image::Rgb([128, 128, 128]))
        .save(dir.join("tex.png"))
        .unwrap();
    std::fs::write(dir.join("refl.exr"), "# nm value\n300 0.5\n900 0.5\n").unwrap();
    let scene = dir.join("scene.ron");
    std::fs::write(
        &scene,
        r#"(
    film: (width: 8, height: 6),
    sampler: (spp: 1),
    materials: {
        "tex": Diffuse(reflectance: Bitmap(path: "tex.png")),
        "file": Diffuse(reflectance: File(path: "refl.exr")),
    },
    shapes: [
        (shape: Sphere(center: (-1, 0, 4)), material: "tex"),
        (shape: Sphere(center: (1, 0, 4)), material: "file"),
    ],
    emitters: [Envmap(filename: "sky.exr")],
)"#,
    )
    .unwrap();
    scene
}

/// Runs prism in `dir`; returns (exit code, stderr).
fn run_in(dir: &Path, args: &[&str]) -> (i32, String) {
    let o = prism().current_dir(dir).args(args).output().unwrap();
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

fn assert_refused(dir: &Path, args: &[&str], needles: &[&str]) {
    let (code, err) = run_in(dir, args);
    assert_eq!(code, 2, "{args:?}: exit code {code}, stderr:\n{err}");
    assert!(err.starts_with("error: "), "{args:?}: {err}");
    assert!(!err.contains("panicked"), "{args:?}: {err}");
    // Refused before rendering: no summary line.
    assert!(
        !err.contains("rendered "),
        "{args:?}: rendered first:\n{err}"
    );
    for n in needles {
        assert!(err.contains(n), "{args:?}: stderr lacks `{n}`:\n{err}");
    }
}

/// Every file in `dir` with its bytes (to show nothing was changed or left behind).
fn snapshot(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut v: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .filter(|e| e.file_type().unwrap().is_file())
        .map(|e| {
            (
                e.file_name().to_string_lossy().into_owned(),
                std::fs::read(e.path()).unwrap(),
            )
        })
        .collect();
    v.sort();
    v
}

/// Issue 14 item 2: an output that is an input of the scene, or the other output, or has the
/// wrong extension, is refused (exit 2, naming the path and the flag) and nothing changes.
#[test]
fn outputs_never_overwrite_inputs() {
    let dir = workdir("inputs");
    scene_with_inputs(&dir);
    // A scene file with an .exr name, and a hard link to the envmap: found by file identity.
    std::fs::copy(dir.join("scene.ron"), dir.join("scene.exr")).unwrap();
    std::fs::hard_link(dir.join("sky.exr"), dir.join("alias.exr")).unwrap();
    let before = snapshot(&dir);
    let cases: &[(&[&str], &[&str])] = &[
        (
            &["render", "scene.exr", "-o", "scene.exr"],
            &["scene.exr: -o", "the scene file being rendered"],
        ),
        (
            &["render", "scene.ron", "-o", "sky.exr"],
            &["sky.exr: -o", "a file this scene reads"],
        ),
        (
            &["render", "scene.ron", "-o", "./sky.exr"],
            &["a file this scene reads"],
        ),
        (
            &["render", "scene.ron", "-o", "alias.exr"],
            &["alias.exr: -o", "a file this scene reads"],
        ),
        (
            &["render", "scene.ron", "-o", "refl.exr"],
            &["refl.exr: -o", "a file this scene reads"],
        ),
        (
            &["render", "scene.ron", "-o", "o.exr", "--preview", "tex.png"],
            &["tex.png: --preview", "a file this scene reads"],
        ),
        (
            &["render", "scene.ron", "-o", "scene.ron"],
            &["scene.ron: -o", "does not end in `.exr`"],
        ),
        (
            &["render", "scene.ron", "-o", "out.png"],
            &["out.png: -o", "does not end in `.exr`"],
        ),
        (
            &["render", "scene.ron", "-o", "o.exr", "--preview", "o.exr"],
            &["--preview", "would overwrite the EXR output"],
        ),
        (
            &["render", "scene.ron", "-o", "o.exr", "--preview", "./o.exr"],
            &["--preview", "would overwrite the EXR output"],
        ),
        (
            &["render", "scene.ron", "-o", "o.exr", "--preview", "p.jpg"],
            &["p.jpg: --preview", "does not end in `.png`"],
        ),
    ];
    for (args, needles) in cases {
        assert_refused(&dir, args, needles);
    }
    // The default output (the scene's name with .exr, here) is checked too.
    std::fs::copy(dir.join("scene.ron"), dir.join("sky.ron")).unwrap();
    assert_refused(
        &dir,
        &["render", "sky.ron"],
        &["sky.exr: -o", "a file this scene reads"],
    );
    std::fs::remove_file(dir.join("sky.ron")).unwrap();
    assert_eq!(snapshot(&dir), before, "a file changed or was left behind");
    // And the renders that are fine still work.
    let (code, err) = run_in(
        &dir,
        &["render", "scene.ron", "-o", "o.exr", "--preview", "o.png"],
    );
    assert_eq!(code, 0, "{err}");
}

/// Issue 14 item 2, export: a mesh the scene reads at `DIR/meshes/0000.ply` is not overwritten.
#[test]
fn export_never_overwrites_a_mesh_it_reads() {
    let dir = workdir("export-inputs");
    std::fs::create_dir_all(dir.join("meshes")).unwrap();
    let ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    std::fs::write(dir.join("meshes/0000.ply"), ply).unwrap();
    std::fs::write(
        dir.join("mesh.ron"),
        r#"(film: (width: 4, height: 4), materials: { "m": Diffuse() }, shapes: [(shape: Mesh(path: "meshes/0000.ply"), material: "m")])"#,
    )
    .unwrap();
    assert_refused(
        &dir,
        &["export", "mesh.ron", "-o", "."],
        &["0000.ply: -o", "a file this scene reads"],
    );
    assert_eq!(
        std::fs::read_to_string(dir.join("meshes/0000.ply")).unwrap(),
        ply
    );
    assert!(!dir.join("scene.json").exists());
    let (code, err) = run_in(&dir, &["export", "mesh.ron", "-o", "out"]);
    assert_eq!(code, 0, "{err}");
    assert!(dir.join("out/meshes/0000.ply").exists());
}

/// A path in a directory this process cannot write: a read-only directory, or (running as
/// root, which may write anywhere) one under /proc.
fn unwritable_dir(dir: &Path) -> PathBuf {
    use std::os::unix::fs::PermissionsExt;
    let ro = dir.join("ro");
    std::fs::create_dir_all(&ro).unwrap();
    std::fs::set_permissions(&ro, std::fs::Permissions::from_mode(0o555)).unwrap();
    if std::fs::write(ro.join("probe"), b"").is_ok() {
        let _ = std::fs::remove_file(ro.join("probe"));
        return PathBuf::from("/proc/prism-test");
    }
    ro
}

/// Issue 14 item 3: unusable output paths are found before rendering (the summary line never
/// appears, no EXR is written), with the path, the flag and a fix; exit 2.
#[test]
fn output_paths_are_checked_before_rendering() {
    let dir = workdir("late");
    std::fs::write(dir.join("scene.ron"), GOOD).unwrap();
    std::fs::create_dir_all(dir.join("d.exr")).unwrap();
    std::fs::write(dir.join("file"), b"x").unwrap();
    let ro = unwritable_dir(&dir);
    let ro_exr = ro.join("x.exr");
    let ro_png = ro.join("x.png");
    let ro_exr = ro_exr.to_str().unwrap();
    let ro_png = ro_png.to_str().unwrap();
    let cases: &[(&[&str], &[&str])] = &[
        (&["-o", "d.exr"], &["d.exr: -o", "is a directory"]),
        (
            &["-o", "file/x.exr"],
            &["file/x.exr: -o", "lies under `file`, which is a file"],
        ),
        (
            &["-o", "file/sub/x.exr"],
            &["lies under `file`, which is a file"],
        ),
        (&["-o", ro_exr], &["x.exr: -o", "hint: choose a writable"]),
        (
            &["-o", "o.exr", "--preview", ro_png],
            &["x.png: --preview", "hint: choose a writable"],
        ),
        (
            &["-o", "o.exr", "--preview", "d.exr/../file/p.png"],
            &["--preview"],
        ),
        (
            &["-o", "o.exr", "--threads", "0"],
            &["--threads must be at least 1"],
        ),
    ];
    for (extra, needles) in cases {
        let args: Vec<&str> = ["render", "scene.ron"]
            .iter()
            .chain(extra.iter())
            .copied()
            .collect();
        assert_refused(&dir, &args, needles);
        assert!(!dir.join("o.exr").exists(), "{args:?} wrote the EXR");
    }
    // A missing directory is created, as before.
    let (code, err) = run_in(
        &dir,
        &[
            "render",
            "scene.ron",
            "-o",
            "new/sub/o.exr",
            "--preview",
            "new/p.png",
        ],
    );
    assert_eq!(code, 0, "{err}");
    assert!(dir.join("new/sub/o.exr").exists() && dir.join("new/p.png").exists());
    // Export into a regular file, or a directory it cannot write: exit 2 as well.
    assert_refused(
        &dir,
        &["export", "scene.ron", "-o", "file"],
        &["-o", "which is a file"],
    );
    if ro.starts_with(&dir) {
        assert_refused(
            &dir,
            &["export", "scene.ron", "-o", ro.to_str().unwrap()],
            &["-o", "hint: choose a writable"],
        );
    }
}

/// Issue 14 item 3: a scene whose file name is not ASCII renders; the `prism:scene` header
/// attribute holds the name's UTF-8 bytes.
#[test]
fn non_ascii_scene_name_renders() {
    let dir = workdir("utf8");
    std::fs::write(dir.join("場景.ron"), GOOD).unwrap();
    let (code, err) = run_in(&dir, &["render", "場景.ron", "-q"]);
    assert_eq!(code, 0, "{err}");
    let meta = exr::meta::MetaData::read_from_file(dir.join("場景.exr"), false).unwrap();
    let h = &meta.headers[0];
    let value = h
        .shared_attributes
        .other
        .iter()
        .chain(h.own_attributes.other.iter())
        .find(|(k, _)| k.bytes() == b"prism:scene")
        .map(|(_, v)| v.clone());
    match value {
        Some(exr::meta::attribute::AttributeValue::Text(t)) => {
            assert_eq!(t.bytes(), "場景.ron".as_bytes())
        }
        other => panic!("prism:scene is {other:?}"),
    }
}

// ---- Interrupted and killed runs. ----

/// A render that runs for a while (64×64 at 3000 spp), printing progress every 10%.
const LONG: &str = r#"(
    film: (width: 64, height: 64),
    sampler: (spp: 3000),
    materials: { "grey": Diffuse(reflectance: Constant(0.5)) },
    shapes: [(shape: Sphere(center: (0, 0, 4)), material: "grey")],
    emitters: [Constant(radiance: Named("D65"))],
)"#;

/// A render that is quick but writes a large EXR (512×512, 22 channels: ~23 MB of floats).
const BIG_WRITE: &str = r#"(
    film: (width: 512, height: 512),
    sampler: (spp: 1),
    outputs: (bands: 16),
    materials: { "grey": Diffuse(reflectance: Constant(0.5)) },
    shapes: [(shape: Sphere(center: (0, 0, 4)), material: "grey")],
    emitters: [Constant(radiance: Named("D65"))],
)"#;

const OLD: &[u8] = b"the previous render, which must survive";

/// A running prism and its stderr lines.
struct Run {
    child: std::process::Child,
    lines: std::sync::mpsc::Receiver<String>,
}

fn spawn(dir: &Path, scene: &str) -> Run {
    std::fs::write(dir.join("scene.ron"), scene).unwrap();
    let mut child = prism()
        .current_dir(dir)
        .args(["render", "scene.ron", "-o", "out.exr"])
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let err = child.stderr.take().unwrap();
    let (tx, lines) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        use std::io::BufRead;
        for l in std::io::BufReader::new(err).lines().map_while(Result::ok) {
            let _ = tx.send(l);
        }
    });
    Run { child, lines }
}

impl Run {
    /// Waits for a stderr line containing `needle` (at most 60 s).
    fn wait_line(&self, needle: &str) {
        let end = std::time::Instant::now() + std::time::Duration::from_secs(60);
        while let Ok(l) = self.lines.recv_timeout(end - std::time::Instant::now()) {
            if l.contains(needle) {
                return;
            }
        }
        panic!("no `{needle}` on stderr");
    }

    /// Waits until the temporary EXR has bytes in it (the write has begun), polling each ms.
    fn wait_writing(&mut self, dir: &Path) {
        let tmp = dir.join(format!(".out.exr.{}.tmp.exr", self.child.id()));
        for _ in 0..60_000 {
            if std::fs::metadata(&tmp).is_ok_and(|m| m.len() > 0) {
                return;
            }
            assert!(
                self.child.try_wait().unwrap().is_none(),
                "prism ended first"
            );
            std::thread::sleep(std::time::Duration::from_millis(1));
        }
        panic!("the EXR write never began");
    }

    fn signal(&self, sig: i32) {
        // SAFETY: sends a signal to our own child, which has not been waited for yet.
        assert_eq!(unsafe { libc::kill(self.child.id() as i32, sig) }, 0);
    }

    /// Waits for the exit (at most 10 s); returns (code, signal, the rest of stderr).
    fn finish(mut self) -> (Option<i32>, Option<i32>, String) {
        use std::os::unix::process::ExitStatusExt;
        let t = std::time::Instant::now();
        let status = loop {
            if let Some(s) = self.child.try_wait().unwrap() {
                break s;
            }
            assert!(t.elapsed().as_secs() < 10, "prism did not exit");
            std::thread::sleep(std::time::Duration::from_millis(5));
        };
        let rest: Vec<String> = self.lines.iter().collect();
        (status.code(), status.signal(), rest.join("\n"))
    }
}

fn temporaries(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains(".tmp."))
        .collect()
}

/// Issue 14 item 4: SIGINT (Ctrl-C) or SIGTERM while rendering or while writing the EXR: prompt
/// exit with a message and 128 + the signal (130, 143), no temporary left, the old EXR intact.
#[test]
fn interrupt_leaves_no_temporary_and_keeps_the_old_output() {
    for (when, sig, code) in [
        ("render", libc::SIGINT, 130),
        ("render", libc::SIGTERM, 143),
        ("write", libc::SIGINT, 130),
    ] {
        let dir = workdir(&format!("int-{when}-{sig}"));
        std::fs::write(dir.join("out.exr"), OLD).unwrap();
        let mut run = spawn(&dir, if when == "render" { LONG } else { BIG_WRITE });
        if when == "render" {
            run.wait_line("progress:");
        } else {
            run.wait_writing(&dir);
        }
        let t = std::time::Instant::now();
        run.signal(sig);
        let (c, _, err) = run.finish();
        assert!(t.elapsed().as_secs_f64() < 3.0, "{when}: slow exit");
        assert_eq!(c, Some(code), "{when} {sig}: {err}");
        assert!(err.contains("error: interrupted by SIG"), "{err}");
        let out = std::fs::read(dir.join("out.exr")).unwrap();
        if when == "write" && out != OLD {
            // The EXR is encoded in memory and lands in one call just before the rename, so
            // the signal can come after the rename: then the new EXR replaced the old one
            // whole, as a rename does (checked: it is a whole EXR), and nothing is lost.
            assert_eq!(&out[..4], &[0x76, 0x2f, 0x31, 0x01], "{when}: not an EXR");
            assert!(exr::prelude::read_all_data_from_file(dir.join("out.exr")).is_ok());
        } else {
            assert_eq!(out, OLD, "{when}");
        }
        assert_eq!(temporaries(&dir), Vec::<String>::new(), "{when} {sig}");
    }
}

/// Issue 14 items 4 and 9: SIGKILL (which no process can handle) at fixed moments: while
/// rendering, just as the EXR write begins, and 30 ms into it. The old EXR is byte-identical
/// each time; the temporary a killed write leaves is swept by the next run in that directory,
/// which leaves other files, and the temporaries of live processes, alone.
#[test]
fn kill_keeps_the_old_output_and_the_next_run_sweeps() {
    let dir = workdir("kill");
    std::fs::write(dir.join("out.exr"), OLD).unwrap();
    let mut killed_writing = 0;
    for moment in ["render", "write", "write+30ms"] {
        let mut run = spawn(&dir, if moment == "render" { LONG } else { BIG_WRITE });
        if moment == "render" {
            run.wait_line("progress:");
        } else {
            run.wait_writing(&dir);
            if moment == "write+30ms" {
                std::thread::sleep(std::time::Duration::from_millis(30));
            }
        }
        run.signal(libc::SIGKILL);
        let pid = run.child.id();
        let (c, s, _) = run.finish();
        if c == Some(0) {
            // The write finished within 30 ms (a fast machine): the new EXR replaced the old
            // one whole, as a rename does; put the old one back for the next moment.
            std::fs::write(dir.join("out.exr"), OLD).unwrap();
            continue;
        }
        assert_eq!(s, Some(libc::SIGKILL), "{moment}");
        assert_eq!(std::fs::read(dir.join("out.exr")).unwrap(), OLD, "{moment}");
        if moment != "render" {
            assert_eq!(temporaries(&dir), [format!(".out.exr.{pid}.tmp.exr")]);
            killed_writing += 1;
        }
    }
    assert!(killed_writing >= 1, "no kill landed during a write");
    // Not ours to remove: a live process's temporary (this test's pid) and other files.
    let live = format!(".other.exr.{}.tmp.exr", std::process::id());
    for keep in [live.as_str(), ".notes.tmp.txt", "a.exr.1.tmp.exr"] {
        std::fs::write(dir.join(keep), b"keep").unwrap();
    }
    std::fs::write(dir.join("scene.ron"), GOOD).unwrap();
    let (code, err) = run_in(&dir, &["render", "scene.ron", "-o", "next.exr", "-q"]);
    assert_eq!(code, 0, "{err}");
    let mut left = temporaries(&dir);
    left.sort();
    assert_eq!(left, [".notes.tmp.txt", live.as_str(), "a.exr.1.tmp.exr"]);
    assert_eq!(std::fs::read(dir.join("out.exr")).unwrap(), OLD);
}

/// Issue 14 item 7: a preview of a film without RGB or XYZ is refused before rendering (exit 2;
/// it was found after the render and exited 1).
#[test]
fn preview_without_colour_channels_is_refused_first() {
    let dir = workdir("preview-channels");
    let scene = GOOD.replace(
        "sampler:",
        "outputs: (rgb: false, xyz: false, bands: 4), sampler:",
    );
    std::fs::write(dir.join("scene.ron"), scene).unwrap();
    assert_refused(
        &dir,
        &["render", "scene.ron", "-o", "o.exr", "--preview", "o.png"],
        &["o.png: --preview", "needs the rgb or xyz output"],
    );
    assert!(!dir.join("o.exr").exists());
}

/// Renders `scene` (written to `dir/name`) expecting exit 2 and each of `needles` on stderr.
fn assert_scene_refused(dir: &Path, name: &str, scene: &[u8], needles: &[&str]) {
    std::fs::write(dir.join(name), scene).unwrap();
    assert_refused(dir, &["render", name, "-o", "o.exr", "-q"], needles);
}

/// Issue 14 item 7: the real problem named. A UTF-8 byte order mark is accepted (skipped).
#[test]
fn parse_errors_name_the_real_problem() {
    let dir = workdir("messages");
    let mut bom = b"\xef\xbb\xbf".to_vec();
    bom.extend_from_slice(GOOD.as_bytes());
    std::fs::write(dir.join("bom.ron"), &bom).unwrap();
    let (code, err) = run_in(&dir, &["render", "bom.ron", "-o", "bom.exr", "-q"]);
    assert_eq!(code, 0, "a BOM is accepted: {err}");
    let mut bad = GOOD.as_bytes().to_vec();
    bad.insert(60, 0xff);
    assert_scene_refused(
        &dir,
        "utf8.ron",
        &bad,
        &["utf8.ron: the file is not UTF-8 text: byte 60 (0xFF, on line 4)"],
    );
    let spp = GOOD.replace("spp: 2", "spp: 1.5");
    assert_scene_refused(
        &dir,
        "int.ron",
        spp.as_bytes(),
        &["int.ron:3:20: expected an integer, got 1.5", "whole number"],
    );
    let width = GOOD.replace("width: 16", "width: 16.0");
    assert_scene_refused(
        &dir,
        "int2.ron",
        width.as_bytes(),
        &["int2.ron:2:19: expected an integer, got 16.0"],
    );
    let deep = format!(
        "(materials: {{\"m\": {}Diffuse(){}}}, shapes: [])",
        "Twosided(bsdf: ".repeat(200),
        ")".repeat(200)
    );
    assert_scene_refused(
        &dir,
        "deep.ron",
        deep.as_bytes(),
        &["nested too deeply (more than 128"],
    );
    // A spectrum file that is not UTF-8: the offset, and no "paths are relative" hint.
    std::fs::write(dir.join("s.txt"), b"400 0.5\n\xfe700 0.5\n").unwrap();
    let file = GOOD.replace("Constant(0.5)", "File(path: \"s.txt\")");
    assert_scene_refused(
        &dir,
        "spec.ron",
        file.as_bytes(),
        &["s.txt: the file is not UTF-8 text: byte 8 (0xFE, on line 2)"],
    );
    let (_, err) = run_in(&dir, &["render", "spec.ron", "-o", "o.exr"]);
    assert!(!err.contains("relative"), "{err}");
}

/// Issue 14 item 7: mesh errors give the OBJ line or PLY element, a PLY whose header counts
/// disagree with its data is refused, huge coordinates are named as such, and a file that was
/// found gets no "paths are relative" hint (a missing one does).
#[test]
fn mesh_errors_give_the_line_and_the_cause() {
    let dir = workdir("mesh-messages");
    let scene = |mesh: &str| {
        format!(
            r#"(film: (width: 8, height: 6), sampler: (spp: 1), materials: {{ "m": Diffuse() }}, shapes: [(shape: Mesh(path: "{mesh}"), material: "m", to_world: [Translate((0, 0, 4))])])"#
        )
    };
    let ply = |nv: usize, nf: usize, body: &str| {
        format!("ply\nformat ascii 1.0\nelement vertex {nv}\nproperty float x\nproperty float y\nproperty float z\nelement face {nf}\nproperty list uchar int vertex_indices\nend_header\n{body}")
    };
    let tri = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    let cases: Vec<(&str, String, Vec<&str>)> = vec![
        (
            "a.obj",
            "v 0 0 0\nv 1 0 0\nv 0 1\nf 1 2 3\n".into(),
            vec!["`a.obj` line 3 (`v 0 1`): OBJ position parse error"],
        ),
        (
            "b.obj",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n".into(),
            vec!["`b.obj` line 4 (`f 1 2 9`): OBJ face vertex index out of bounds"],
        ),
        (
            "c.obj",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n".into(),
            vec!["`c.obj` line 4 (`f 1 2 x`): OBJ face parse error"],
        ),
        (
            "big.obj",
            "v 1e30 0 0\nv 0 1e30 0\nv 0 0 1e30\nf 1 2 3\n".into(),
            vec![
                "coordinates are too large (up to 1e30",
                "scale the mesh down",
            ],
        ),
        (
            "zero.obj",
            "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n".into(),
            vec!["every triangle of this shape has zero area"],
        ),
        (
            "more.ply",
            ply(5, 1, tri),
            vec!["`more.ply`: the header declares 5 `vertex` elements, but the file ends"],
        ),
        (
            "faces.ply",
            ply(3, 2, tri),
            vec!["the header declares 2 `face` elements, but the file ends"],
        ),
        (
            "fewer.ply",
            ply(3, 1, &format!("{tri}3 0 1 2\n")),
            vec!["data after the elements the header declares (3 vertex, 1 face)"],
        ),
        (
            "text.ply",
            ply(3, 1, "0 0 0\n1 0 zz\n0 1 0\n3 0 1 2\n"),
            vec!["PLY element `vertex`: Line 11", "(`1 0 zz`)"],
        ),
        (
            "index.ply",
            ply(3, 1, "0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n"),
            vec!["face 0 uses vertex 7, but the file has 3 vertices"],
        ),
    ];
    for (mesh, text, needles) in &cases {
        std::fs::write(dir.join(mesh), text).unwrap();
        assert_scene_refused(&dir, "m.ron", scene(mesh).as_bytes(), needles);
        let (_, err) = run_in(&dir, &["render", "m.ron", "-o", "o.exr"]);
        assert!(!err.contains("relative to the scene"), "{mesh}: {err}");
    }
    assert_scene_refused(
        &dir,
        "m.ron",
        scene("missing.obj").as_bytes(),
        &["hint: mesh paths are relative to the scene file"],
    );
    // The same PLY with matching counts loads.
    std::fs::write(dir.join("ok.ply"), ply(3, 1, tri)).unwrap();
    std::fs::write(dir.join("m.ron"), scene("ok.ply")).unwrap();
    let (code, err) = run_in(&dir, &["render", "m.ron", "-o", "o.exr", "-q"]);
    assert_eq!(code, 0, "{err}");
}

/// The pixels (every channel, as bits) of an EXR prism wrote.
fn pixels(path: &Path) -> Vec<(String, Vec<u32>)> {
    use exr::prelude::*;
    let img = read_all_flat_layers_from_file(path).unwrap();
    let mut v: Vec<_> = img.layer_data[0]
        .channel_data
        .list
        .iter()
        .map(|c| {
            let bits = c.sample_data.values_as_f32().map(f32::to_bits).collect();
            (c.name.to_string(), bits)
        })
        .collect();
    v.sort();
    v
}

/// Determinism through the binary: the same scene and seed give bit-identical pixels with 1,
/// 2 and 7 worker threads (the Cornell box at 32×32, 4 spp, and a scene with textures, a
/// spectrum file and an environment map).
#[test]
fn one_two_and_seven_threads_give_identical_pixels() {
    let dir = workdir("threads");
    let cornell =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cornell.ron"))
            .unwrap()
            .replace("width: 256, height: 256", "width: 32, height: 32");
    std::fs::write(dir.join("cornell.ron"), cornell).unwrap();
    scene_with_inputs(&dir);
    for scene in ["cornell.ron", "scene.ron"] {
        let mut first = None;
        for t in ["1", "2", "7"] {
            let out = format!("{scene}.{t}.exr");
            let (code, err) = run_in(
                &dir,
                &[
                    "render",
                    scene,
                    "-o",
                    &out,
                    "--spp",
                    "4",
                    "--seed",
                    "3",
                    "--threads",
                    t,
                    "-q",
                ],
            );
            assert_eq!(code, 0, "{err}");
            let p = pixels(&dir.join(&out));
            assert!(
                p.iter().any(|(_, b)| b.iter().any(|&x| x != 0)),
                "{scene}: black"
            );
            match &first {
                None => first = Some(p),
                Some(f) => assert!(f == &p, "{scene}: {t} threads differ from 1"),
            }
        }
    }
}

/// Issue 14 item 7: the field that holds the NaN is named (a sphere's NaN center was reported
/// as its radius), and IOR hints fit the form written.
#[test]
fn nan_field_and_ior_hints() {
    let dir = workdir("nan-ior");
    let center = GOOD.replace("center: (0, 0, 4)", "center: (0, NaN, 4)");
    assert_scene_refused(
        &dir,
        "c.ron",
        center.as_bytes(),
        &["shapes[0].shape.center: a sphere needs a finite center (got [0.0, NaN, 4.0])"],
    );
    let ior = |v: &str| {
        GOOD.replace(
            "Diffuse(reflectance: Constant(0.5))",
            &format!("Dielectric(int_ior: {v})"),
        )
    };
    let cases: &[(&str, &[&str])] = &[
        (
            "-1.5",
            &[
                "int_ior: an index of refraction must be > 0, not -1.5",
                "e.g. 1.5 (glass)",
            ],
        ),
        (
            "NaN",
            &[
                "int_ior: the index of refraction NaN is not a finite number",
                "e.g. 1.5 (glass)",
            ],
        ),
        ("Cauchy(a: -1.5, b: 0)", &["reaches -1.5", "n = a + b/λ²"]),
        (
            "Spectrum(Tabulated([(400, 1.5), (600, 1.5)]))",
            &["reaches 0", "must cover the whole spectral range"],
        ),
        (
            "Sellmeier(b: (1, 0, 0), c: (0.25, 0, 0))",
            &["not a finite number somewhere", "makes a pole"],
        ),
    ];
    for (v, needles) in cases {
        assert_scene_refused(&dir, "ior.ron", ior(v).as_bytes(), needles);
        let (_, err) = run_in(&dir, &["render", "ior.ron", "-o", "o.exr"]);
        if !v.starts_with("Spectrum") {
            assert!(!err.contains("tabulated"), "{v}: {err}");
        }
        if !v.starts_with("Sellmeier") {
            assert!(!err.contains("Sellmeier"), "{v}: {err}");
        }
    }
}
