//! Bad time input (issue 30 item 5): keyframes out of order, shared or non-finite times, a
//! shutter that closes before it opens, shears in keys, a non-finite `--time`:
//! each exits 2 naming the file, the field and the fix, before rendering.

mod scratch;
use std::path::Path;
use std::process::Command;

fn workdir(name: &str) -> scratch::Scratch {
    scratch::scratch("motion", name)
}

/// A small scene with `camera` and `shape` fields spliced in.
fn scene(camera: &str, shape: &str) -> String {
    format!(
        r#"(
    camera: ({camera}),
    film: (width: 8, height: 6),
    sampler: (spp: 1),
    shapes: [(shape: Sphere(center: (0, 0, 4)){shape})],
    emitters: [Constant(radiance: Named("D65"))],
)"#
    )
}

/// Writes `text` as scene.ron, runs `prism render scene.ron extra…`; asserts exit 2 with
/// every needle in stderr, and that nothing was rendered.
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
    assert!(
        err.starts_with("error: ") && !err.contains("panicked"),
        "{name}: {err}"
    );
    assert!(
        !Path::new(&dir.join("scene.exr")).exists(),
        "{name}: rendered"
    );
    for n in ["scene.ron"].iter().chain(needles) {
        assert!(err.contains(n), "{name}: stderr lacks `{n}`:\n{err}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

const KEY0: &str = "(time: 0, to_world: [Translate((0, 0, 0))])";

#[test]
fn keys_out_of_order_are_refused() {
    let s = scene(
        "",
        &format!(", animation: (keys: [{KEY0}, (time: 2), (time: 1)])"),
    );
    refused(
        "order",
        &s,
        &[],
        &[
            "shapes[0].animation.keys[2].time",
            "out of order",
            "increasing time",
        ],
    );
}

#[test]
fn keys_sharing_a_time_are_refused() {
    let s = scene("", &format!(", animation: (keys: [{KEY0}, (time: 0)])"));
    refused(
        "dup",
        &s,
        &[],
        &[
            "shapes[0].animation.keys[1].time",
            "share the time",
            "a time of its own",
        ],
    );
}

#[test]
fn non_finite_key_times_are_refused() {
    for (i, t) in ["NaN", "inf", "-inf"].iter().enumerate() {
        let s = scene(
            &format!("animation: (keys: [(time: {t}, to_world: [Translate((0, 0, 0))])])"),
            "",
        );
        refused(
            &format!("nan{i}"),
            &s,
            &[],
            &[
                "camera.animation.keys[0].time",
                "not a finite number of seconds",
            ],
        );
    }
}

#[test]
fn a_shutter_closing_before_it_opens_is_refused() {
    let s = scene("shutter: (open: 0.5, close: 0.25)", "");
    refused(
        "shutter",
        &s,
        &[],
        &["camera.shutter.close", "before it opens", "close ≥ open"],
    );
    let s = scene("shutter: (open: 0, close: 1, readout: -1)", "");
    refused("readout", &s, &[], &["camera.shutter.readout", "≥ 0"]);
    let s = scene("shutter: (open: NaN, close: 1)", "");
    refused("open_nan", &s, &[], &["camera.shutter.open", "finite"]);
}

#[test]
fn an_animation_beside_to_world_is_refused() {
    let s = scene(
        "",
        &format!(", to_world: [Scale((2, 2, 2))], animation: (keys: [{KEY0}])"),
    );
    refused(
        "both",
        &s,
        &[],
        &[
            "shapes[0].to_world",
            "both to_world and animation",
            "each key's to_world",
        ],
    );
}

#[test]
fn a_sheared_key_is_refused() {
    let s = scene(
        "",
        ", animation: (keys: [(time: 0, to_world: [Scale((3, 1, 1)), Rotate(axis: (0, 0, 1), angle: 30), Scale((1, 2, 1))])])",
    );
    refused(
        "shear",
        &s,
        &[],
        &["shapes[0].animation.keys[0].to_world", "shears"],
    );
}

#[test]
fn a_camera_key_that_scales_unequally_is_refused() {
    let s = scene(
        "animation: (keys: [(time: 0), (time: 1, to_world: [Scale((1, 2, 1))])]), shutter: (open: 0, close: 1)",
        "",
    );
    refused(
        "camscale",
        &s,
        &[],
        &["camera.animation.keys[1].to_world", "uniform scale"],
    );
}

#[test]
fn a_non_finite_time_flag_is_refused() {
    refused(
        "flag",
        &scene("", ""),
        &["--time", "NaN"],
        &["--time NaN", "finite"],
    );
}
