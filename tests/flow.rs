//! Flow layers (issue 30 item 3): the occlusion mask and the flow of a moving object (a RON
//! shape, a glTF model moved by RON keys or by its own node animation) against
//! closed forms, and flow's bad inputs (item 5), which exit 2 naming the file, field and fix.
//!
//! The closed-form scenes use an orthographic camera 8 units wide looking along −z, so a
//! world point (x, y) is seen at OpenCV pixel ((x + 4)·W/8 − 0.5, (h/2 − y)·W/8 − 0.5) at
//! every depth: a point moving by (dx, dy) flows by (dx, −dy)·W/8 pixels.

mod scratch;
use prism::film::Film;
use prism::math::portable;
use std::path::Path;
use std::process::Command;

const W: u32 = 40;
const H: u32 = 20;

/// A scene: the orthographic camera above, `shapes`, fps 10 (step 0.1 s), rendered at `t`.
fn scene(t: f32, aovs: &str, shapes: &str) -> String {
    format!(
        r#"(
    camera: (model: Orthographic(width: 8), fps: 10, shutter: (open: {t}, close: {t}),
        to_world: [LookAt(origin: (0, 0, 10), target: (0, 0, 0), up: (0, 1, 0))]),
    film: (width: {W}, height: {H}),
    sampler: (spp: 1),
    aovs: [{aovs}],
    shapes: [{shapes}],
    emitters: [Constant(radiance: Named("D65"))],
)"#
    )
}

fn layers(text: &str) -> Film {
    let job = prism::load::load_str(text, Path::new("inline.ron")).unwrap();
    prism::pipeline::render(&job, 1.0, &|_| {}).film
}

/// A unit sphere sliding along x from −3 (t = 0) to 9 (t = 2): 0.6 units per 0.1 s step.
const SLIDING: &str = r#"(shape: Sphere(radius: 1), animation: (keys: [
    (time: 0, to_world: [Translate((-3, 0, 0))]), (time: 2, to_world: [Translate((9, 0, 0))])]))"#;

fn ids(f: &Film) -> Vec<u32> {
    f.uint_channels
        .iter()
        .find(|c| c.name == "instance.ID")
        .expect("instance.ID")
        .data
        .clone()
}

/// Every pixel on the sliding sphere flows by its closed-form motion (0.6 units right =
/// 3 px; backward 3 px left) and its scene flow is (±0.6, 0, 0) in the world; in the camera
/// frame (x right, y down, z forward, camera still) it is the same vector. Background pixels
/// flow 0 and are marked. Tolerance 1e-4 px: f32 rounding of the hit point (≈1e-6 units).
#[test]
fn a_sliding_sphere_flows_by_its_closed_form() {
    let f = layers(&scene(
        0.5,
        r#""flow_forward", "flow_backward", "scene_flow_forward", "scene_flow_backward_camera", "flow_forward_occlusion", "instance""#,
        SLIDING,
    ));
    let ch = |n: &str| f.channel(n).unwrap_or_else(|| panic!("{n}")).to_vec();
    let (fx, fy, bx) = (
        ch("flow_forward.X"),
        ch("flow_forward.Y"),
        ch("flow_backward.X"),
    );
    let (sx, cx, occ) = (
        ch("scene_flow_forward.X"),
        ch("scene_flow_backward_camera.X"),
        ch("flow_forward_occlusion.M"),
    );
    let id = ids(&f);
    let px = 0.6 * W as f32 / 8.0;
    let mut on = 0;
    for i in 0..(W * H) as usize {
        if id[i] == 0 {
            assert_eq!(
                (fx[i], fy[i], sx[i], occ[i]),
                (0.0, 0.0, 0.0, 1.0),
                "pixel {i}"
            );
            continue;
        }
        on += 1;
        assert!(
            (fx[i] - px).abs() < 1e-4 && fy[i].abs() < 1e-4,
            "pixel {i}: {} {}",
            fx[i],
            fy[i]
        );
        assert!((bx[i] + px).abs() < 1e-4, "pixel {i}: backward {}", bx[i]);
        assert!(
            (sx[i] - 0.6).abs() < 1e-5 && (cx[i] + 0.6).abs() < 1e-5,
            "pixel {i}"
        );
        assert_eq!(occ[i], 0.0, "pixel {i}: nothing hides the sphere");
    }
    assert!(on > 50, "{on} pixels on the sphere");
}

/// A wall (a box in front, x ≥ 1) hides the sliding sphere's points that pass x = 1 within
/// the step, and points leaving the image (x ≥ 4) are marked: the mask is 1 exactly where the
/// closed form says, on every pixel of the sphere farther than 0.05 units from either edge
/// (rounding decides the pixels on the edge itself).
#[test]
fn the_occlusion_mask_marks_hidden_and_leaving_points() {
    let wall = r#"(shape: Cube, to_world: [Scale((2, 3, 0.1)), Translate((3, 0, 3))])"#;
    // At t = 0.6 the centre is at 0.6 and moves to 1.2: points x ∈ [0.4, 1.6] pass x = 1.
    let f = layers(&scene(
        0.6,
        r#""flow_forward_occlusion", "position", "instance""#,
        &format!("{SLIDING}, {wall}"),
    ));
    let occ = f.channel("flow_forward_occlusion.M").unwrap();
    let pos = f.channel("position.X").unwrap();
    let id = ids(&f);
    let (mut hidden, mut seen) = (0, 0);
    for i in 0..(W * H) as usize {
        if id[i] != 1 {
            continue; // the wall (instance 2) or background
        }
        let x2 = pos[i] + 0.6;
        if (x2 - 1.0).abs() < 0.05 {
            continue;
        }
        let want = if x2 > 1.0 { 1.0 } else { 0.0 };
        assert_eq!(occ[i], want, "pixel {i}: x {} → {x2}", pos[i]);
        if want == 1.0 {
            hidden += 1;
        } else {
            seen += 1;
        }
    }
    assert!(hidden > 10 && seen > 10, "hidden {hidden}, seen {seen}");
    // Leaving the image: at t = 0.95 the centre moves from 2.7 to 3.3, and points passing
    // x = 4 (the image's right edge, OpenCV pixel 39.5) leave.
    let f = layers(&scene(
        0.95,
        r#""flow_forward_occlusion", "position", "instance""#,
        SLIDING,
    ));
    let occ = f.channel("flow_forward_occlusion.M").unwrap();
    let pos = f.channel("position.X").unwrap();
    let id = ids(&f);
    let mut left = 0;
    for i in 0..(W * H) as usize {
        let x2 = pos[i] + 0.6;
        if id[i] == 0 || (x2 - 4.0).abs() < 0.05 {
            continue;
        }
        let want = if x2 > 4.0 { 1.0 } else { 0.0 };
        assert_eq!(occ[i], want, "pixel {i}: x {} → {x2}", pos[i]);
        left += (want == 1.0) as u32;
    }
    assert!(left > 5, "{left} pixels leave the image");
}

/// A render with flow layers has the same colour channels as one without (the flow scene is
/// built apart and the colour pass never sees it).
#[test]
fn flow_layers_leave_the_colour_unchanged() {
    let a = layers(&scene(0.5, r#""flow_forward""#, SLIDING));
    let b = layers(&scene(0.5, "", SLIDING));
    for c in &b.channels {
        let x = a.channel(&c.name).unwrap();
        assert!(
            x.iter()
                .zip(&c.data)
                .all(|(p, q)| p.to_bits() == q.to_bits()),
            "{} differs",
            c.name
        );
    }
}

fn workdir(name: &str) -> scratch::Scratch {
    scratch::scratch("flow", name)
}

/// Writes `text` as scene.ron, runs `prism render scene.ron extra…`; asserts exit 2 with the
/// file and every needle in stderr, and that nothing was rendered.
fn refused(name: &str, text: &str, extra: &[&str], needles: &[&str]) {
    let dir = workdir(name);
    std::fs::write(dir.join("scene.ron"), text).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_prism"))
        .current_dir(&dir)
        .args(["render", "scene.ron", "-q"])
        .args(extra)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{name}: {err}");
    assert!(!err.contains("panicked"), "{name}: {err}");
    assert!(!dir.join("scene.exr").exists(), "{name}: rendered");
    for n in ["scene.ron"].iter().chain(needles) {
        assert!(err.contains(n), "{name}: stderr lacks `{n}`:\n{err}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn flow_without_a_frame_rate_is_refused() {
    let s = scene(0.5, r#""flow_forward""#, SLIDING).replace("fps: 10, ", "");
    refused(
        "nofps",
        &s,
        &[],
        &["camera.fps", "flow_forward", "--fps 30"],
    );
    // --fps gives it.
    let dir = workdir("cli-fps");
    std::fs::write(dir.join("scene.ron"), &s).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_prism"))
        .current_dir(&dir)
        .args(["render", "scene.ron", "-q", "--fps", "10"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_bad_frame_rate_is_refused() {
    for (k, fps) in ["0", "-24", "NaN", "inf"].iter().enumerate() {
        let s = scene(0.5, r#""flow_forward""#, SLIDING).replace("fps: 10", &format!("fps: {fps}"));
        refused(&format!("badfps{k}"), &s, &[], &["camera.fps", "positive"]);
    }
}

#[test]
fn flow_of_a_still_scene_is_refused() {
    let s = scene(0.5, r#""flow_backward""#, "(shape: Sphere(radius: 1))");
    refused(
        "still",
        &s,
        &[],
        &["aovs[0]", "nothing in the scene moves", "animate"],
    );
}

#[test]
fn flow_beyond_the_keys_is_refused() {
    // The keys span [0, 2]; at t = 1.95 the next frame (2.05) lies past them.
    let s = scene(1.95, r#""instance", "flow_forward""#, SLIDING);
    refused("next", &s, &[], &["aovs[1]", "no next frame", "2.05"]);
    let s = scene(0.05, r#""flow_backward""#, SLIDING);
    refused("previous", &s, &[], &["aovs[0]", "no previous frame"]);
    // --time moves the frame: the same scene at 0.5 renders.
    let dir = workdir("cli-time");
    std::fs::write(dir.join("scene.ron"), &s).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_prism"))
        .current_dir(&dir)
        .args(["render", "scene.ron", "-q", "--time", "0.5"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let _ = std::fs::remove_dir_all(&dir);
}

/// Flow on glTF models. A still glTF (tests/data/gltf/Box.gltf) given the sliding sphere's
/// RON `animation` flows by the same closed form, 0.6 units = 3 px right on every pixel of it.
/// Khronos' AnimatedTriangle turns by its own node animation 360° per second about +z through
/// its node's origin c (here (0, −0.5, 0), scaled 2), LINEAR between keys 90° apart (slerp:
/// uniform in time): a point p seen at t = 0.3 is at c + R_z(36°)(p − c) one 0.1 s step later,
/// so its flow is that displacement in pixels (dx, −dy)·W/8, from the `position` layer's p.
/// Tolerance 1e-3 px: f32 rounding of p and of the slerped rotation (≈1e-6 units, 5 px/unit).
#[test]
fn gltf_models_flow_by_their_closed_form() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR"));
    let bx = data.join("tests/data/gltf/Box.gltf");
    let sliding = SLIDING.replace("Sphere(radius: 1)", &format!("Gltf(path: {bx:?})"));
    let f = layers(&scene(0.5, r#""flow_forward", "instance""#, &sliding));
    let (fx, fy, id) = (
        f.channel("flow_forward.X").unwrap().to_vec(),
        f.channel("flow_forward.Y").unwrap().to_vec(),
        ids(&f),
    );
    let px = 0.6 * W as f32 / 8.0;
    let on: Vec<usize> = (0..(W * H) as usize).filter(|&i| id[i] != 0).collect();
    assert!(on.len() > 20, "{} pixels on the box", on.len());
    for &i in &on {
        assert!(
            (fx[i] - px).abs() < 1e-3 && fy[i].abs() < 1e-3,
            "box pixel {i}: {} {}",
            fx[i],
            fy[i]
        );
    }

    let tri = data.join("scenes/motion/AnimatedTriangle.gltf");
    let shape = format!(
        "(shape: Gltf(path: {tri:?}), to_world: [Scale((2, 2, 2)), Translate((0, -0.5, 0))])"
    );
    let f = layers(&scene(
        0.3,
        r#""flow_forward", "position", "instance""#,
        &shape,
    ));
    let ch = |n: &str| f.channel(n).unwrap_or_else(|| panic!("{n}")).to_vec();
    let (fx, fy, x, y) = (
        ch("flow_forward.X"),
        ch("flow_forward.Y"),
        ch("position.X"),
        ch("position.Y"),
    );
    let id = ids(&f);
    let (s, c) = portable::sin_cos(36f32.to_radians());
    let mut on = 0;
    for i in 0..(W * H) as usize {
        if id[i] == 0 {
            continue;
        }
        on += 1;
        let (px, py) = (x[i], y[i] + 0.5);
        let (dx, dy) = (c * px - s * py - px, s * px + c * py - py);
        let (want_x, want_y) = (dx * W as f32 / 8.0, -dy * W as f32 / 8.0);
        assert!(
            (fx[i] - want_x).abs() < 1e-3 && (fy[i] - want_y).abs() < 1e-3,
            "triangle pixel {i}: flow ({}, {}), closed form ({want_x}, {want_y})",
            fx[i],
            fy[i]
        );
    }
    assert!(on > 20, "{on} pixels on the triangle");
}

/// Flow of nested motion: Khronos' AnimatedTriangle (its node turning 360° per second about
/// +z through the node's origin) moved by the shape's own RON keys, which slide it from
/// x = −2 to 2 over [0, 1] s (scaled 2, at y = −0.5): world(t) = RON(t) · node(t). A point
/// p seen at t = 0.3 is one 0.1 s step later at c' + R_z(36°)(p − c), c = (−2 + 4t, −0.5)
/// the node's origin then (c' = c + (0.4, 0)), so its flow is that displacement in pixels
/// (dx, −dy)·W/8, from the `position` layer's p. Tolerance 1e-3 px, as above.
#[test]
fn nested_gltf_motion_flows_by_its_closed_form() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR"));
    let tri = data.join("scenes/motion/AnimatedTriangle.gltf");
    let shape = format!(
        r#"(shape: Gltf(path: {tri:?}), animation: (keys: [
        (time: 0, to_world: [Scale((2, 2, 2)), Translate((-2, -0.5, 0))]),
        (time: 1, to_world: [Scale((2, 2, 2)), Translate((2, -0.5, 0))])]))"#
    );
    let f = layers(&scene(
        0.3,
        r#""flow_forward", "position", "instance""#,
        &shape,
    ));
    let ch = |n: &str| f.channel(n).unwrap_or_else(|| panic!("{n}")).to_vec();
    let (fx, fy, x, y) = (
        ch("flow_forward.X"),
        ch("flow_forward.Y"),
        ch("position.X"),
        ch("position.Y"),
    );
    let id = ids(&f);
    let (s, c) = portable::sin_cos(36f32.to_radians());
    let centre = (-2.0 + 4.0 * 0.3f32, -0.5f32);
    let mut on = 0;
    for i in 0..(W * H) as usize {
        if id[i] == 0 {
            continue;
        }
        on += 1;
        let (px, py) = (x[i] - centre.0, y[i] - centre.1);
        let (dx, dy) = (c * px - s * py - px + 0.4, s * px + c * py - py);
        let (want_x, want_y) = (dx * W as f32 / 8.0, -dy * W as f32 / 8.0);
        assert!(
            (fx[i] - want_x).abs() < 1e-3 && (fy[i] - want_y).abs() < 1e-3,
            "triangle pixel {i}: flow ({}, {}), closed form ({want_x}, {want_y})",
            fx[i],
            fy[i]
        );
    }
    assert!(on > 20, "{on} pixels on the triangle");
}
