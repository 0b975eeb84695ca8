//! `prism dataset` light variations: named CIE illuminants (D, F, LED series) beside the
//! blackbody temperature, drawn per frame; bad names and clashing fields refused.

mod dataset_util;
use dataset_util::*;

const LAMP: &str = "(target: \"lamp\", intensity: (6, 18), temperature: (2700, 6500))";

/// Each frame's lamp is one of the listed illuminants times its intensity: the JSON names it,
/// the exported scene (what `prism render` reproduces bit for bit, dataset_runs.rs) holds
/// `Scaled(intensity, Named(it))`, and 8 frames draw more than one of the three (all eight
/// alike has p = 3·(1/3)^8 ≈ 5e-4; seed fixed, so this is deterministic).
#[test]
fn lights_take_named_illuminants_per_frame() {
    let dir = workdir("illuminants");
    let names = ["F2", "LED-B1", "D50"];
    let cfg = config(&dir, |t| {
        assert!(t.contains(LAMP));
        t.replace(
            LAMP,
            "(target: \"lamp\", intensity: (6, 18), illuminants: [\"F2\", \"LED-B1\", \"D50\"])",
        )
    });
    let out = dir.join("out");
    ok(&dataset(&cfg, &out, &[]));
    let mut seen = std::collections::BTreeSet::new();
    for i in 0..8 {
        let f = json_file(&out.join(format!("frames/{i:06}.json")));
        let lamp = &f["frame"]["lights"][0];
        let n = lamp["illuminant"].as_str().unwrap().to_string();
        assert!(names.contains(&n.as_str()), "frame {i}: {lamp}");
        if i < 2 {
            let exp = dir.join("exp");
            ok(&dataset(&cfg, &exp, &["--export-frame", &i.to_string()]));
            let ron = std::fs::read_to_string(exp.join(format!("frames/{i:06}.ron"))).unwrap();
            assert!(ron.contains(&format!("Named(\"{n}\")")), "frame {i}: {ron}");
        }
        seen.insert(n);
    }
    assert!(seen.len() >= 2, "{seen:?}");
}

#[test]
fn bad_illuminant_variations_are_refused() {
    let dir = workdir("bad-illuminants");
    let cases: [(&str, &[&str]); 3] = [
        (
            "(target: \"lamp\", illuminants: [\"D65\", \"F99\"])",
            &[
                "lights[0].illuminants[1]",
                "unknown illuminant \"F99\"",
                "LED-B1",
            ],
        ),
        (
            "(target: \"lamp\", temperature: (3000, 4000), illuminants: [\"D65\"])",
            &["lights[0].illuminants", "not both"],
        ),
        (
            "(target: \"emitters[0]\", illuminants: [\"D65\"])",
            &["lights[0].illuminants", "environment map"],
        ),
    ];
    for (k, (lamp, needles)) in cases.into_iter().enumerate() {
        let cfg = config(&dir, |t| t.replace(LAMP, lamp));
        let out = dir.join(format!("out{k}"));
        refused(&dataset(&cfg, &out, &[]), needles);
        assert!(!out.exists(), "case {k}: the output folder was made");
    }
}

/// A table `nm value` from `lo` to `hi` nm every 10 nm, each value `f(nm)`.
fn spd(lo: u32, hi: u32, f: impl Fn(f64) -> f64) -> String {
    let rows = (lo..=hi)
        .step_by(10)
        .map(|nm| format!("{nm} {}\n", f(nm as f64)));
    format!("nm value\n{}", rows.collect::<String>())
}

/// `illuminant_files` are drawn beside the named illuminants: frames name the file as the
/// config does, the exported scene holds `Scaled(intensity / Y, File(<absolute path>))` with Y
/// the file's luminance (a flat 2.0 has Y = 2, so the factor is intensity / 2 to 1e-5, the
/// f32 rounding of the luminance integral), and `dataset.json` hashes the files.
#[test]
fn lights_take_illuminant_files_beside_named_ones() {
    let dir = workdir("illuminant-files");
    std::fs::create_dir_all(dir.join("spd")).unwrap();
    std::fs::write(dir.join("spd/flat.txt"), spd(300, 900, |_| 2.0)).unwrap();
    std::fs::write(dir.join("spd/ramp.txt"), spd(350, 850, |nm| nm / 500.0)).unwrap();
    let cfg = config(&dir, |t| {
        t.replace(
            LAMP,
            "(target: \"lamp\", intensity: (6, 18), illuminants: [\"D65\"], illuminant_files: [\"spd/flat.txt\", \"spd/ramp.txt\"])",
        )
    });
    let out = dir.join("out");
    ok(&dataset(&cfg, &out, &[]));
    let ds = json_file(&out.join("dataset.json"));
    for f in ["spd/flat.txt", "spd/ramp.txt"] {
        assert!(
            ds["inputs"][f].is_string(),
            "{f} not hashed: {}",
            ds["inputs"]
        );
    }
    let mut seen = std::collections::BTreeSet::new();
    let exp = dir.join("exp");
    for i in 0..8 {
        let f = json_file(&out.join(format!("frames/{i:06}.json")));
        let lamp = &f["frame"]["lights"][0];
        let n = lamp["illuminant"].as_str().unwrap().to_string();
        if n == "spd/flat.txt" {
            ok(&dataset(&cfg, &exp, &["--export-frame", &i.to_string()]));
            let ron = std::fs::read_to_string(exp.join(format!("frames/{i:06}.ron"))).unwrap();
            let path = format!("{:?}", dir.join("spd/flat.txt"));
            let at = ron
                .find(&path)
                .unwrap_or_else(|| panic!("frame {i}: {ron}"));
            let head = &ron[..at];
            let scaled = head.rfind("Scaled(").expect("a Scaled spectrum");
            let factor: f64 = head[scaled + 7..]
                .split(',')
                .next()
                .unwrap()
                .trim()
                .parse()
                .unwrap();
            let want = lamp["intensity"].as_f64().unwrap() / 2.0;
            assert!(
                (factor / want - 1.0).abs() < 1e-5,
                "frame {i}: {factor} vs {want}"
            );
        }
        seen.insert(n);
    }
    assert!(
        seen.contains("spd/flat.txt") && seen.contains("spd/ramp.txt"),
        "{seen:?}"
    );
}

/// A missing, unparsable, too short, negative or dark illuminant file, or one beside
/// `temperature`, is refused at `--check` (exit 2, the config, the field, the fix), before
/// any frame or folder is made.
#[test]
fn bad_illuminant_files_are_refused_at_check() {
    let dir = workdir("bad-illuminant-files");
    std::fs::create_dir_all(dir.join("spd")).unwrap();
    std::fs::write(dir.join("spd/text.txt"), "this is not a table\n").unwrap();
    std::fs::write(dir.join("spd/short.txt"), spd(400, 700, |_| 1.0)).unwrap();
    std::fs::write(
        dir.join("spd/negative.txt"),
        spd(300, 900, |nm| if nm == 550.0 { -1.0 } else { 1.0 }),
    )
    .unwrap();
    std::fs::write(dir.join("spd/dark.txt"), spd(300, 900, |_| 0.0)).unwrap();
    std::fs::write(dir.join("spd/ok.txt"), spd(300, 900, |_| 1.0)).unwrap();
    let lamp = |files: &str, extra: &str| {
        format!("(target: \"lamp\", {extra}illuminant_files: [\"spd/ok.txt\", {files}])")
    };
    let cases: [(String, &[&str]); 6] = [
        (
            lamp("\"spd/gone.txt\"", ""),
            &["lights[0].illuminant_files[1]", "gone.txt"],
        ),
        (
            lamp("\"spd/text.txt\"", ""),
            &["lights[0].illuminant_files[1]", "text.txt"],
        ),
        (
            lamp("\"spd/short.txt\"", ""),
            &["illuminant_files[1]", "400–700 nm", "360–830 nm"],
        ),
        (
            lamp("\"spd/negative.txt\"", ""),
            &["illuminant_files[1]", "550 nm is -1"],
        ),
        (
            lamp("\"spd/dark.txt\"", ""),
            &["illuminant_files[1]", "luminance 0"],
        ),
        (
            lamp("\"spd/ok.txt\"", "temperature: (3000, 4000), "),
            &["lights[0].illuminant_files", "not both"],
        ),
    ];
    for (k, (lamp, needles)) in cases.into_iter().enumerate() {
        let cfg = config(&dir, |t| t.replace(LAMP, &lamp));
        let out = dir.join(format!("out{k}"));
        let o = dataset(&cfg, &out, &["--check"]);
        refused(&o, needles);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            err.contains("dataset.ron"),
            "case {k}: no config named: {err}"
        );
        assert!(!out.exists(), "case {k}: the output folder was made");
    }
}
