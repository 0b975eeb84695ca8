//! `prism dataset` camera intrinsics and distortion ranges (src/dataset/intrinsics.rs): K and
//! OpenCV's coefficients drawn per frame, the sidecar's K and dist equal to the draws, and
//! ranges refused at `--check` when any corner of them folds the frame.

mod dataset_util;
use dataset_util::*;

const CAMERA: &str =
    "        fov: (35, 50),\n        roll: 3,\n        keep_in_view: [\"ball\"],\n";

/// smoke.ron's camera with `fields` instead of its fov, roll and keep_in_view.
fn camera(fields: &'static str) -> impl Fn(String) -> String {
    move |t: String| {
        assert!(t.contains(CAMERA), "smoke.ron's camera changed");
        t.replace(CAMERA, fields)
    }
}

const DRAWN: &str = "        intrinsics: (fx: (52, 64), cx: (30.5, 32.5), cy: (22.5, 24.5)),\n        distortion: (k1: (-0.12, 0.0), k2: (0.0, 0.02), p1: (-0.001, 0.001)),\n";

/// Frames 0..4: the JSON's drawn K and distortion are the sidecar's (K to 1e-6 relative: the
/// camera holds it as f32 tan(half fov) and offset; dist exactly, it is kept as drawn), they
/// lie in their ranges and differ between frames; frame 1's export renders the same pixels.
#[test]
fn intrinsics_and_distortion_are_drawn_per_frame_and_recorded() {
    let dir = workdir("intrinsics");
    let cfg = config(&dir, camera(DRAWN));
    let out = dir.join("out");
    ok(&dataset(&cfg, &out, &["--frames", "0..4"]));
    let mut fxs = Vec::new();
    for i in 0..4 {
        let f = json_file(&out.join(format!("frames/{i:06}.json")));
        let drawn = &f["frame"]["intrinsics"];
        let cam = &f["camera"];
        assert_eq!(cam["dist"], drawn["distortion"], "frame {i}");
        assert_eq!(cam["model"], "pinhole+distortion", "frame {i}");
        for r in 0..3 {
            for c in 0..3 {
                let (a, b) = (
                    cam["K"][r][c].as_f64().unwrap(),
                    drawn["K"][r][c].as_f64().unwrap(),
                );
                assert!(
                    (a - b).abs() <= 1e-6 * b.abs().max(1.0),
                    "frame {i}: K[{r}][{c}] {a} vs {b}"
                );
            }
        }
        let k = &drawn["K"];
        let fx = k[0][0].as_f64().unwrap();
        assert_eq!(
            k[1][1].as_f64().unwrap(),
            fx,
            "fy = fx when fy has no range"
        );
        assert!((52.0..=64.0).contains(&fx), "{fx}");
        let cx = k[0][2].as_f64().unwrap();
        assert!((30.5..=32.5).contains(&cx), "{cx}");
        let k1 = drawn["distortion"][0].as_f64().unwrap();
        assert!((-0.12..=0.0).contains(&k1), "{k1}");
        assert_eq!(
            drawn["distortion"][4].as_f64(),
            Some(0.0),
            "k3 has no range"
        );
        fxs.push(fx);
    }
    fxs.dedup();
    assert_eq!(fxs.len(), 4, "{fxs:?}");
    let exp = dir.join("exp");
    ok(&dataset(&cfg, &exp, &["--export-frame", "1"]));
    let exr = dir.join("r1.exr");
    ok(&prism()
        .arg("render")
        .arg(exp.join("frames/000001.ron"))
        .arg("-o")
        .arg(&exr)
        .arg("--quiet")
        .output()
        .unwrap());
    let (want, got) = (exr_pixels(&out.join("frames/000001.exr")), exr_pixels(&exr));
    assert_eq!(
        want.keys().collect::<Vec<_>>(),
        got.keys().collect::<Vec<_>>()
    );
    for (k, v) in &want {
        assert!(got[k] == *v, "channel {k} differs from the export's render");
    }
}

/// Ranges that fold the frame at one corner of their box, a non-positive fx, K beside fov, and
/// distortion with keep_in_view are refused at `--check`: exit 2, the field and the fix.
#[test]
fn ranges_that_could_fold_the_frame_are_refused_at_check() {
    let dir = workdir("intrinsics-bad");
    let cases: [(&'static str, &[&str]); 5] = [
        (
            // The ranges' middle (k1 -0.06, k2 -0.25) maps the frame one-to-one; the corner
            // k2 = -1 folds at undistorted radius ~0.64, inside the frame's corner (~0.77).
            "        intrinsics: (fx: (52, 64), cx: (30.5, 32.5), cy: (22.5, 24.5)),\n        distortion: (k1: (-0.12, 0.0), k2: (-1.0, 0.5)),\n",
            &["camera.distortion", "corner", "k2", "narrow the ranges"],
        ),
        (
            "        intrinsics: (fx: (0, 64), cx: (30.5, 32.5), cy: (22.5, 24.5)),\n",
            &["camera.intrinsics.fx", "positive"],
        ),
        (
            "        intrinsics: (fx: (64, 52), cx: (30.5, 32.5), cy: (22.5, 24.5)),\n",
            &["camera.intrinsics.fx", "lo ≤ hi"],
        ),
        (
            "        fov: (35, 50),\n        intrinsics: (fx: (52, 64), cx: (30.5, 32.5), cy: (22.5, 24.5)),\n",
            &["camera.intrinsics", "fov"],
        ),
        (
            "        keep_in_view: [\"ball\"],\n        distortion: (k1: (-0.1, 0.0)),\n",
            &["camera.distortion", "keep_in_view"],
        ),
    ];
    for (k, (fields, needles)) in cases.into_iter().enumerate() {
        let cfg = config(&dir, camera(fields));
        let out = dir.join(format!("out{k}"));
        refused(&dataset(&cfg, &out, &["--check"]), needles);
        assert!(!out.exists(), "case {k}: the output folder was made");
    }
}
