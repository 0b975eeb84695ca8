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
