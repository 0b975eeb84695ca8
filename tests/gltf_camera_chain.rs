//! A glTF camera under every motion the importer reads (issue 30): nested animated nodes, a
//! camera offset from a turning node (it sweeps an arc), CUBICSPLINE channels and STEP mixed
//! with LINEAR. `prism render model.gltf` gives the camera the node chain's motion, so with an
//! open shutter it poses, blurs and flows exactly as the file says. Each closed form below is
//! written from the channels, independently of the importer.

mod gltf_rig;
mod scratch;
use glam::{DVec2, DVec3, Mat4, Vec3};
use gltf_rig::{blur_against_instants, model, small, Channel, T01, TURN};
use prism::config::ShutterConfig;
use prism::math::portable;
use std::f32::consts::PI;
use std::path::Path;

/// glTF's camera half-turn about y, to prism's camera frame.
fn flip() -> Mat4 {
    Mat4::from_diagonal(glam::Vec4::new(-1.0, 1.0, -1.0, 1.0))
}

/// The camera's turn at t: slerp from the identity to the half-turn about y of `TURN`, which
/// turns at a constant rate, π·t about y.
fn turn(t: f32) -> Mat4 {
    prism::math::rotation::axis_angle(Vec3::Y, PI * t.clamp(0.0, 1.0))
}

/// The cubic translation's keys (glTF CUBICSPLINE: in-tangent, value, out-tangent per key).
const CUBIC: &[f32] = &[
    0.0, 0.0, 0.0, 0.0, 0.0, 5.0, 6.0, 0.0, 0.0, //
    0.0, 1.0, 0.0, 1.0, 0.5, 5.0, 0.0, 0.0, 0.0,
];

/// glTF's cubic Hermite on [0, 1] (key interval 1) for `CUBIC`: p0 (0, 0, 5), out-tangent
/// (6, 0, 0), p1 (1, 0.5, 5), in-tangent (0, 1, 0): over the blur's [0, 0.2] s it slides 0.87
/// along x where a straight line between the keys slides 0.2.
fn hermite(t: f32) -> Vec3 {
    let u = t.clamp(0.0, 1.0);
    let (u2, u3) = (u * u, u * u * u);
    Vec3::new(0.0, 0.0, 5.0) * (2.0 * u3 - 3.0 * u2 + 1.0)
        + Vec3::new(6.0, 0.0, 0.0) * (u3 - 2.0 * u2 + u)
        + Vec3::new(1.0, 0.5, 5.0) * (-2.0 * u3 + 3.0 * u2)
        + Vec3::new(0.0, 1.0, 0.0) * (u3 - u2)
}

type Case = (&'static str, String, fn(f32) -> Mat4);

/// The motions, each a glTF file and the camera's world transform at t (prism's frame).
fn cases() -> Vec<Case> {
    let slide: Channel = (
        1,
        "translation",
        "LINEAR",
        T01,
        &[0.0, 0.0, 1.0, 1.0, 0.5, 1.0],
    );
    let spin: Channel = (2, "rotation", "LINEAR", T01, TURN);
    vec![
        // The rig slides, the camera 4 in front of it turns on its own node.
        (
            "nested",
            model("", r#", "translation": [0, 0, 4]"#, &[slide, spin]),
            |t| {
                Mat4::from_translation(Vec3::new(t, 0.5 * t, 5.0).min(Vec3::new(1.0, 0.5, 5.0)))
                    * turn(t)
                    * flip()
            },
        ),
        // The rig (1 above the quad) turns; the camera 4 from its origin orbits it.
        (
            "arc",
            model(
                r#", "translation": [0, 0, 1]"#,
                r#", "translation": [0, 0, 4]"#,
                &[(1, "rotation", "LINEAR", T01, TURN)],
            ),
            |t| {
                Mat4::from_translation(Vec3::Z)
                    * turn(t)
                    * Mat4::from_translation(Vec3::new(0.0, 0.0, 4.0))
                    * flip()
            },
        ),
        // The camera's own node: a CUBICSPLINE translation and a LINEAR turn.
        (
            "cubic",
            model(
                "",
                "",
                &[(2, "translation", "CUBICSPLINE", T01, CUBIC), spin],
            ),
            |t| Mat4::from_translation(hermite(t)) * turn(t) * flip(),
        ),
        // STEP translation (jumps at 1 s) with a LINEAR turn.
        (
            "step",
            model(
                "",
                "",
                &[
                    (
                        2,
                        "translation",
                        "STEP",
                        T01,
                        &[0.0, 0.0, 5.0, 1.0, 0.5, 5.0],
                    ),
                    spin,
                ],
            ),
            |t| {
                let at = if t < 1.0 {
                    Vec3::new(0.0, 0.0, 5.0)
                } else {
                    Vec3::new(1.0, 0.5, 5.0)
                };
                Mat4::from_translation(at) * turn(t) * flip()
            },
        ),
    ]
}

fn write(dir: &Path, name: &str, text: &str) -> std::path::PathBuf {
    let p = dir.join(format!("{name}.gltf"));
    std::fs::write(&p, text).unwrap();
    p
}

fn max_diff(a: Mat4, b: Mat4) -> f32 {
    (a - b)
        .abs()
        .to_cols_array()
        .into_iter()
        .fold(0f32, f32::max)
}

/// With the shutter open over [0, 1] s the traced camera motion (`motion::Timing`) is the
/// closed form at 101 times, and at instants (`--time`) the camera is posed there, to 1e-5
/// (f32 rounding of slerp and the products). Before, each of these was refused.
#[test]
fn a_gltf_camera_under_any_motion_is_posed_by_its_closed_form() {
    let dir = scratch::scratch("gltf-chain", "poses");
    let mut bad = Vec::new();
    for (name, text, pose) in cases() {
        let p = write(&dir, name, &text);
        let job = prism::load::load(&p, |cfg| {
            small(cfg, 1, 1);
            cfg.camera.shutter = Some(ShutterConfig {
                open: 0.0,
                close: 1.0,
                readout: 0.0,
            });
        })
        .unwrap_or_else(|e| panic!("{name}: {e}"));
        let timing = job.scene.timing.as_ref().expect("an open shutter");
        let (m, _) = timing.camera.as_ref().expect("a moving camera");
        let worst = (0..=100)
            .map(|i| i as f32 / 100.0)
            .map(|t| (max_diff(m.matrix(t), pose(t)), t))
            .fold((0f32, 0f32), |a, b| if b.0 > a.0 { b } else { a });
        if worst.0 >= 1e-5 {
            bad.push(format!("{name}: traced {} off at {} s", worst.0, worst.1));
        }
        for t in [0.25f32, 0.6] {
            let job = prism::load::load(&p, |cfg| prism::load::motion::set_time(cfg, t)).unwrap();
            let got = job.scene.camera.to_world().m;
            if max_diff(got, pose(t)) >= 1e-5 {
                bad.push(format!("{name}: at the instant {t}: {got} vs {}", pose(t)));
            }
        }
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

/// The blur of each moving camera equals the mean of its instants (the tolerance is
/// `gltf_rig::blur_against_instants`'): 5σ of the noise plus 2% for the midpoint rule; the
/// camera held at mid-shutter must fail it, so the motion is seen.
#[test]
fn a_gltf_camera_under_any_motion_blurs_as_its_instants() {
    let dir = scratch::scratch("gltf-chain", "blur");
    let mut bad = Vec::new();
    for (name, text, _) in cases().into_iter().take(3) {
        let p = write(&dir, name, &text);
        let (worst, still) = blur_against_instants(&p);
        eprintln!("{name}: worst column {worst:.3} of its tolerance; held camera {still:.2}");
        if worst >= 1.0 || still <= 1.0 {
            bad.push(format!(
                "{name}: blur {worst:.3}, held {still:.2} of the tolerance"
            ));
        }
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

/// OpenCV pixel (corner at 0, centres at i + 0.5) of world point `x` seen by the pinhole with
/// world transform `pose` (prism's frame: +x left, +y up, +z forward), vertical field of view
/// 0.9 rad (the file's yfov) on the 24 × 18 film of `small`.
fn project(pose: Mat4, x: DVec3) -> DVec2 {
    let c = pose.as_dmat4().inverse().transform_point3(x);
    let f = 9.0 / portable::tan(0.45f64);
    DVec2::new(12.0 + f * -c.x / c.z, 9.0 + f * -c.y / c.z)
}

/// Forward flow of the still scene seen by each moving camera at t = 0.1 s (fps 20: the next
/// frame at 0.15 s): every pixel's `position` point, projected with the closed-form pose of
/// the next frame, lands at the pixel centre plus its flow, to 1e-3 px (f32 rounding of the
/// hit point and the pose, ≈1e-5 px here); projected with this frame's pose it lands on the
/// pixel centre (a check of the projection itself).
#[test]
fn a_gltf_camera_under_any_motion_flows_by_its_closed_form() {
    let dir = scratch::scratch("gltf-chain", "flow");
    let mut bad = Vec::new();
    for (name, text, pose) in cases().into_iter().take(3) {
        let p = write(&dir, name, &text);
        let job = prism::load::load(&p, |cfg| {
            small(cfg, 1, 1);
            prism::load::motion::set_time(cfg, 0.1);
            cfg.camera.fps = Some(20.0);
            cfg.aovs = vec!["flow_forward".into(), "position".into(), "instance".into()];
        })
        .unwrap_or_else(|e| panic!("{name}: {e}"));
        let film = prism::pipeline::render(&job, 1.0, &|_| {}).film;
        let ch = |n: &str| film.channel(n).unwrap_or_else(|| panic!("{n}")).to_vec();
        let (fx, fy) = (ch("flow_forward.X"), ch("flow_forward.Y"));
        let (x, y, z) = (ch("position.X"), ch("position.Y"), ch("position.Z"));
        let id = &film
            .uint_channels
            .iter()
            .find(|c| c.name == "instance.ID")
            .expect("instance.ID")
            .data;
        // Pixels whose point this frame's pose does not project to their centre: the frame's
        // own camera is not the closed form.
        let (mut on, mut worst, mut off) = (0, 0f64, 0);
        for i in 0..24 * 18 {
            if id[i] == 0 {
                continue;
            }
            on += 1;
            let centre = DVec2::new((i % 24) as f64 + 0.5, (i / 24) as f64 + 0.5);
            let point = DVec3::new(x[i] as f64, y[i] as f64, z[i] as f64);
            let now = project(pose(0.1), point);
            if (now - centre).abs().max_element() >= 1e-3 {
                off += 1;
                continue;
            }
            let want = project(pose(0.15), point) - centre;
            let got = DVec2::new(fx[i] as f64, fy[i] as f64);
            let d = (got - want).abs().max_element();
            if d > worst {
                worst = d;
                if d >= 1e-3 {
                    bad.push(format!("{name}: pixel {i} flows {got}, closed form {want}"));
                }
            }
        }
        eprintln!("{name}: worst flow error {worst:.2e} px over {on} pixels");
        if off > 0 {
            bad.push(format!(
                "{name}: {off} of {on} pixels' points project off their centres (the frame's pose)"
            ));
        }
        assert!(on > 50, "{name}: {on} pixels on the model");
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}
