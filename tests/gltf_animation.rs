//! glTF 2.0 animations (issue 30 item 1): node poses at instants against the spec's formulas
//! evaluated here from the file's keys (LINEAR slerp, STEP, CUBICSPLINE Hermite with tangents
//! scaled by the key interval), a spinning model's motion blur against its closed-form
//! coverage, nested motion (an animated node under an animated node, under the shape's own
//! RON animation) blurred as the mean of its instants, and bad animation data refused (item 5).

mod scratch;
use glam::{DMat4, DQuat, DVec3, Vec3};
use prism::film::Film;
use prism::math::portable;
use prism::shape::Shape;
use std::path::{Path, PathBuf};
use std::process::Command;

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/gltf")
        .join(name)
}

fn workdir(name: &str) -> scratch::Scratch {
    scratch::scratch("gltf-anim", name)
}

/// A RON scene including the glTF file `model` (black), with `camera` fields and the shape's
/// `extra` fields spliced in: a white world seen by an orthographic camera 8 units wide.
fn scene(model: &Path, w: u32, h: u32, spp: u32, camera: &str, extra: &str) -> String {
    format!(
        r#"(
    camera: (model: Orthographic(width: 8), to_world: [LookAt(origin: (0, 0, 5), target: (0, 0, 0), up: (0, 1, 0))]{camera}),
    film: (width: {w}, height: {h}, filter: Box()),
    sampler: (spp: {spp}, seed: 9),
    spectral: (sampling: Uniform, range: (500, 600), wavelengths: 1),
    outputs: (rgb: false, xyz: false, bands: 1, band_range: (500, 600)),
    materials: {{ "black": Diffuse(reflectance: Constant(0.0)) }},
    shapes: [(shape: Gltf(path: "{}"), material: "black"{extra})],
    emitters: [Constant(radiance: Constant(1.0))],
)"#,
        model.display()
    )
}

/// The world positions of the scene's first shape (a copied mesh) at the instant `t`, as
/// `prism render --time t` builds it.
fn positions_at(dir: &Path, model: &Path, t: f32) -> Vec<Vec3> {
    let p = dir.join("at.ron");
    std::fs::write(&p, scene(model, 4, 4, 1, "", "")).unwrap();
    let job = prism::load::load(&p, |cfg| prism::load::motion::set_time(cfg, t)).unwrap();
    match &job.scene.shapes[0] {
        Shape::Mesh(m) => m.positions.clone(),
        _ => panic!("not a mesh"),
    }
}

/// Khronos' AnimatedTriangle: five LINEAR rotation keys about z at 0, ¼, ½, ¾, 1 s of 0°, 90°,
/// 180°, 270°, 360° (quaternions stored to 3 decimals, normalised on reading). Slerp turns at
/// constant speed, so the corner (1, 0, 0) is at angle 360° · t (held after 1 s): to 1e-5.
#[test]
fn animated_triangle_turns_as_its_keys_say() {
    let dir = workdir("triangle");
    let model = data("AnimatedTriangle.gltf");
    for t in [0.0f32, 0.1, 0.25, 0.4, 0.625, 0.9, 1.5] {
        let p = positions_at(&dir, &model, t);
        let a = (t.min(1.0) as f64) * std::f64::consts::TAU;
        let want = [
            (0.0, 0.0),
            (portable::cos(a), portable::sin(a)),
            (-portable::sin(a), portable::cos(a)),
        ];
        for (k, (x, y)) in want.iter().enumerate() {
            let d = portable::hypot(p[k].x as f64 - x, p[k].y as f64 - y);
            assert!(
                d < 1e-5 && p[k].z.abs() < 1e-6,
                "t {t} corner {k}: {}",
                p[k]
            );
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A channel of a generated file: (path, interpolation, times, outputs, output type).
type Channel<'a> = (&'a str, &'a str, Vec<f32>, Vec<f32>, &'a str);

/// A glTF document of one triangle (0,0,0), (1,0,0), (0,1,0) on node 1, under node 0 (`parent`:
/// its JSON fields), with `channels` on node 1: (path, interpolation, times, outputs,
/// output type).
fn doc(parent: &str, channels: &[Channel]) -> String {
    let on: Vec<(usize, Channel)> = channels.iter().map(|c| (1, c.clone())).collect();
    doc_on(parent, &on)
}

/// As `doc`, each channel on its own node (0: the parent, 1: the child with the mesh).
fn doc_on(parent: &str, channels: &[(usize, Channel)]) -> String {
    let mut bytes: Vec<u8> = Vec::new();
    let mut views = Vec::new();
    let mut accessors = Vec::new();
    let mut push = |v: &[f32], ty: &str, count: usize, extra: &str| {
        views.push(format!(
            r#"{{"buffer": 0, "byteOffset": {}, "byteLength": {}}}"#,
            bytes.len(),
            v.len() * 4
        ));
        accessors.push(format!(
            r#"{{"bufferView": {}, "componentType": 5126, "count": {count}, "type": "{ty}"{extra}}}"#,
            views.len() - 1
        ));
        v.iter().for_each(|x| bytes.extend(x.to_le_bytes()));
    };
    push(
        &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0],
        "VEC3",
        3,
        r#", "min": [0, 0, 0], "max": [1, 1, 0]"#,
    );
    let mut samplers = Vec::new();
    let mut chans = Vec::new();
    for (k, (node, (path, interp, times, out, ty))) in channels.iter().enumerate() {
        push(times, "SCALAR", times.len(), "");
        let width = match *ty {
            "VEC4" => 4,
            "VEC3" => 3,
            _ => 1,
        };
        push(out, ty, out.len() / width, "");
        samplers.push(format!(
            r#"{{"input": {}, "output": {}, "interpolation": "{interp}"}}"#,
            1 + 2 * k,
            2 + 2 * k
        ));
        chans.push(format!(
            r#"{{"sampler": {k}, "target": {{"node": {node}, "path": "{path}"}}}}"#
        ));
    }
    let uri = format!(
        "data:application/octet-stream;base64,{}",
        base64::encode(&bytes)
    );
    format!(
        r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}],
  "nodes": [{{"children": [1]{parent}}}, {{"mesh": 0}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}}}]}}],
  "animations": [{{"name": "Move", "samplers": [{}], "channels": [{}]}}],
  "buffers": [{{"byteLength": {}, "uri": "{uri}"}}],
  "bufferViews": [{}], "accessors": [{}]}}"#,
        samplers.join(", "),
        chans.join(", "),
        bytes.len(),
        views.join(", "),
        accessors.join(", ")
    )
}

/// The spec's cubic Hermite spline (glTF 2.0 Appendix C) between keys k and k + 1 of
/// (in-tangent, value, out-tangent) triples `out` (each `n` wide) at times `ts`, evaluated
/// here in f64; before the first key the first value, after the last the last.
fn hermite(ts: &[f64], out: &[f64], n: usize, t: f64) -> Vec<f64> {
    let val = |k: usize, j: usize| out[(3 * k + j) * n..(3 * k + j + 1) * n].to_vec();
    if t <= ts[0] {
        return val(0, 1);
    }
    let last = ts.len() - 1;
    if t >= ts[last] {
        return val(last, 1);
    }
    let k = ts.iter().rposition(|&x| x <= t).unwrap();
    let td = ts[k + 1] - ts[k];
    let s = (t - ts[k]) / td;
    let (s2, s3) = (s * s, s * s * s);
    let (v0, b0, a1, v1) = (val(k, 1), val(k, 2), val(k + 1, 0), val(k + 1, 1));
    (0..n)
        .map(|i| {
            (2.0 * s3 - 3.0 * s2 + 1.0) * v0[i]
                + td * (s3 - 2.0 * s2 + s) * b0[i]
                + (-2.0 * s3 + 3.0 * s2) * v1[i]
                + td * (s3 - s2) * a1[i]
        })
        .collect()
}

/// A child node with CUBICSPLINE translation and rotation and STEP scale, under a parent that
/// translates, turns and scales uniformly: its triangle's corners at seven instants (before,
/// on and between keys, after) against parent · T(t) · R(t) · S(t) computed here from the
/// keys by the spec's formulas (rotation: the Hermite of the components, normalised). To 1e-4
/// (f32 against f64 over coordinates up to ~10).
#[test]
fn cubic_and_step_channels_follow_the_spec() {
    let s = std::f32::consts::FRAC_1_SQRT_2;
    let t_times = vec![0.0f32, 1.0, 3.0];
    #[rustfmt::skip]
    let t_out = vec![
        0.0, 0.0, 0.0,  0.0, 0.0, 0.0,  2.0, 0.0, 0.0,
        0.5, 0.0, 0.0,  1.0, 0.0, 0.0,  0.0, 1.0, 0.0,
        0.0, 1.0, 0.0,  1.0, 2.0, 0.0,  0.0, 0.0, 0.0f32,
    ];
    let r_times = vec![0.0f32, 2.0];
    #[rustfmt::skip]
    let r_out = vec![
        0.0, 0.0, 0.0, 0.0,  0.0, 0.0, 0.0, 1.0,  0.3, 0.0, 0.0, 0.0,
        0.2, 0.0, 0.0, -0.1, s, 0.0, 0.0, s,      0.0, 0.0, 0.0, 0.0f32,
    ];
    let s_times = vec![0.0f32, 1.5];
    let s_out = vec![1.0f32, 1.0, 1.0, 2.0, 1.0, 0.5];
    let parent = r#", "translation": [1, 2, 3], "rotation": [0, 0, 0.70710677, 0.70710677], "scale": [2, 2, 2]"#;
    let text = doc(
        parent,
        &[
            (
                "translation",
                "CUBICSPLINE",
                t_times.clone(),
                t_out.clone(),
                "VEC3",
            ),
            (
                "rotation",
                "CUBICSPLINE",
                r_times.clone(),
                r_out.clone(),
                "VEC4",
            ),
            ("scale", "STEP", s_times, s_out, "VEC3"),
        ],
    );
    let dir = workdir("cubic");
    let model = dir.join("anim.gltf");
    std::fs::write(&model, text).unwrap();
    let f64s = |v: &[f32]| v.iter().map(|&x| x as f64).collect::<Vec<f64>>();
    let p = DMat4::from_scale_rotation_translation(
        DVec3::splat(2.0),
        DQuat::from_rotation_z(std::f64::consts::FRAC_PI_2),
        DVec3::new(1.0, 2.0, 3.0),
    );
    for t in [-0.5f64, 0.0, 0.4, 1.0, 1.7, 2.9, 3.5] {
        let tr = hermite(&f64s(&t_times), &f64s(&t_out), 3, t);
        let q = hermite(&f64s(&r_times), &f64s(&r_out), 4, t);
        let q = DQuat::from_xyzw(q[0], q[1], q[2], q[3]).normalize();
        let sc = if t < 1.5 {
            DVec3::ONE
        } else {
            DVec3::new(2.0, 1.0, 0.5)
        };
        let m = p * DMat4::from_scale_rotation_translation(sc, q, DVec3::new(tr[0], tr[1], tr[2]));
        let got = positions_at(&dir, &model, t as f32);
        for (k, c) in [DVec3::ZERO, DVec3::X, DVec3::Y].iter().enumerate() {
            let want = m.transform_point3(*c);
            let d = (got[k].as_dvec3() - want).length();
            assert!(d < 1e-4, "t {t} corner {k}: {} vs {want}", got[k]);
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

fn values(film: &Film) -> Vec<f32> {
    film.channel("S0.550,000000nm").expect("the band").to_vec()
}

/// AnimatedTriangle scaled by 3 turns 90° while the shutter is open (0 to ¼ s), black on
/// white. A point at polar (r, φ) is covered at turn θ when ψ = φ − θ ∈ [0, 90°] and
/// r (cos ψ + sin ψ) ≤ 3; the turn is uniform in time (slerp), so its covered fraction is
/// that of 2048 evenly spaced θ. Each pixel (16 × 16 points) must match within 5 Bernoulli
/// standard deviations at 256 spp; the model at one instant fails by far.
#[test]
fn a_spinning_gltf_model_blurs_as_its_sweep() {
    let (w, h, spp) = (32u32, 32u32, 256u32);
    let model = data("AnimatedTriangle.gltf");
    let extra = ", to_world: [Scale((3, 3, 3))]";
    let blur = values(&render(&scene(
        &model,
        w,
        h,
        spp,
        ", shutter: (open: 0, close: 0.25)",
        extra,
    )));
    let still = values(&render(&scene(&model, w, h, spp, "", extra)));
    let covered = |x: f64, y: f64| {
        let (r, phi) = (portable::hypot(x, y), portable::atan2(y, x));
        let n = 2048;
        (0..n)
            .filter(|&i| {
                let th = (i as f64 + 0.5) / n as f64 * std::f64::consts::FRAC_PI_2;
                let psi = (phi - th).rem_euclid(std::f64::consts::TAU);
                psi <= std::f64::consts::FRAC_PI_2
                    && r * (portable::cos(psi) + portable::sin(psi)) <= 3.0
            })
            .count() as f64
            / n as f64
    };
    let unit = 8.0 / w as f64;
    let (mut worst, mut still_worst) = (0.0f64, 0.0f64);
    let bound = 5.0 * 0.5 / (spp as f64).sqrt();
    for py in 0..h {
        for px in 0..w {
            let mut c = 0.0;
            for k in 0..256 {
                let fx = px as f64 + ((k % 16) as f64 + 0.5) / 16.0;
                let fy = py as f64 + ((k / 16) as f64 + 0.5) / 16.0;
                c += covered((fx - 0.5 * w as f64) * unit, (0.5 * h as f64 - fy) * unit);
            }
            let want = 1.0 - c / 256.0;
            let i = (py * w + px) as usize;
            worst = worst.max((blur[i] as f64 - want).abs());
            still_worst = still_worst.max((still[i] as f64 - want).abs());
        }
    }
    eprintln!(
        "spinning glTF: worst pixel error {worst:.4} (bound {bound:.4}); still {still_worst:.3}"
    );
    assert!(worst < bound, "worst pixel error {worst} ≥ {bound}");
    assert!(still_worst > 2.0 * bound, "the still model passes too");
}

fn render(text: &str) -> Film {
    let job = prism::load::load_str(text, Path::new("inline.ron")).unwrap();
    prism::integrator::render(&job.scene, &job.settings, &job.channels, &|_| {}).0
}

/// Runs `prism render scene.ron` on a scene including `gltf` (written as anim.gltf, with
/// `args` after its path); asserts exit 2, no panic, and every needle in stderr.
fn refused(name: &str, gltf: &str, args: &str, needles: &[&str]) {
    let dir = workdir(name);
    std::fs::write(dir.join("anim.gltf"), gltf).unwrap();
    let text = scene(
        Path::new("anim.gltf"),
        8,
        6,
        1,
        ", shutter: (open: 0, close: 1)",
        "",
    )
    .replace(
        "Gltf(path: \"anim.gltf\")",
        &format!("Gltf(path: \"anim.gltf\"{args})"),
    );
    std::fs::write(dir.join("scene.ron"), text).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_prism"))
        .current_dir(&dir)
        .args(["render", "scene.ron", "-q"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{name}: {err}");
    assert!(!err.contains("panicked"), "{name}: {err}");
    assert!(!dir.join("scene.exr").exists(), "{name}: rendered");
    for n in needles {
        assert!(err.contains(n), "{name}: stderr lacks `{n}`:\n{err}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_gltf_animations_are_refused() {
    let tr = |times: Vec<f32>, out: Vec<f32>, interp: &str, ty: &str| {
        doc("", &[("translation", interp, times, out, ty)])
    };
    let three = vec![0.0f32; 9];
    refused(
        "order",
        &tr(vec![0.0, 1.0, 0.5], three.clone(), "LINEAR", "VEC3"),
        "",
        &[
            "anim.gltf",
            "animations[0].samplers[0].input",
            "increase",
            "key 1 is at 1 s",
        ],
    );
    refused(
        "nan",
        &tr(vec![0.0, f32::NAN, 2.0], three.clone(), "LINEAR", "VEC3"),
        "",
        &["anim.gltf", "animations[0].samplers[0].input", "increase"],
    );
    refused(
        "count",
        &tr(vec![0.0, 1.0], three.clone(), "LINEAR", "VEC3"),
        "",
        &[
            "anim.gltf",
            "animations[0].samplers[0].output",
            "2 key times but 3 outputs",
            "one per key",
        ],
    );
    refused(
        "cubic_count",
        &tr(vec![0.0, 1.0, 2.0], three.clone(), "CUBICSPLINE", "VEC3"),
        "",
        &["animations[0].samplers[0].output", "three per key"],
    );
    refused(
        "type",
        &tr(vec![0.0, 1.0, 2.0], vec![0.0; 12], "LINEAR", "VEC4"),
        "",
        &[
            "animations[0].samplers[0].output",
            "must be a VEC3 accessor",
            "not VEC4",
        ],
    );
    refused(
        "name",
        &tr(vec![0.0, 1.0, 2.0], three, "LINEAR", "VEC3"),
        ", animation: \"Run\"",
        &[
            "anim.gltf",
            "no animation named or numbered \"Run\"",
            "0 (\"Move\")",
        ],
    );
}

/// Nested motion under an open shutter: the triangle's node (1) slides along its parent's x
/// while the parent (0) turns 90° about z, and the shape's own RON keys slide and turn the
/// whole model: world(t) = RON(t) · parent(t) · child(t), three moving transforms. The blur
/// over [0, 1] s at 256 spp must equal the mean of 32 instants (each posed by `--time`'s
/// static walk, not the chain) at 32 spp, per pixel within 5 standard deviations of the two
/// Bernoulli means plus 1% (the instants are a 32-point quadrature of the time average).
/// The model at one instant fails by far.
#[test]
fn nested_motion_blurs_as_the_mean_of_its_instants() {
    let (w, h, spp, k) = (32u32, 32u32, 256u32, 32u32);
    let turn = |deg: f32| {
        let (s, c) = portable::sin_cos(deg.to_radians() / 2.0);
        vec![0.0, 0.0, s, c]
    };
    let mut rot = turn(0.0);
    rot.extend(turn(90.0));
    let text = doc_on(
        r#", "scale": [1.5, 1.5, 1.5]"#,
        &[
            (0, ("rotation", "LINEAR", vec![0.0, 1.0], rot, "VEC4")),
            (
                1,
                (
                    "translation",
                    "LINEAR",
                    vec![0.0, 1.0],
                    vec![0.0, 0.0, 0.0, 1.0, 0.0, 0.0],
                    "VEC3",
                ),
            ),
        ],
    );
    let dir = workdir("nested");
    let model = dir.join("anim.gltf");
    std::fs::write(&model, text).unwrap();
    let extra = r#", animation: (keys: [
        (time: 0, to_world: [Translate((-1.5, -0.5, 0))]),
        (time: 1, to_world: [Rotate(axis: (0, 0, 1), angle: 20), Translate((0.5, 0, 0))])])"#;
    let blur = values(&render(&scene(
        &model,
        w,
        h,
        spp,
        ", shutter: (open: 0, close: 1)",
        extra,
    )));
    let mut avg = vec![0.0f64; blur.len()];
    for i in 0..k {
        let t = (i as f32 + 0.5) / k as f32;
        let text = scene(
            &model,
            w,
            h,
            spp / 8,
            &format!(", shutter: (open: {t}, close: {t})"),
            extra,
        );
        for (a, v) in avg.iter_mut().zip(values(&render(&text))) {
            *a += v as f64 / k as f64;
        }
    }
    let still = values(&render(&scene(&model, w, h, spp, "", extra)));
    let (n1, n2) = (spp as f64, (spp / 8 * k) as f64);
    let (mut worst, mut still_worst, mut moving) = (0.0f64, 0.0f64, 0);
    for i in 0..blur.len() {
        let (b, a) = (blur[i] as f64, avg[i]);
        let tol = 5.0 * (b * (1.0 - b) / n1 + a * (1.0 - a) / n2).sqrt() + 0.01;
        worst = worst.max((b - a).abs() / tol);
        still_worst = still_worst.max((still[i] as f64 - a).abs() / tol);
        if a > 0.02 && a < 0.98 {
            moving += 1;
        }
    }
    eprintln!("nested blur vs instants: worst {worst:.3} of the tolerance; still {still_worst:.2}");
    assert!(worst < 1.0, "a pixel differs by {worst} of its tolerance");
    assert!(still_worst > 3.0, "the model at one instant passes too");
    assert!(moving > 40, "only {moving} pixels see the model move");
    let _ = std::fs::remove_dir_all(&dir);
}
