//! The packet kernel (`integrator::packet`): the same bits at every packet width and thread
//! count, and the same bits as the scalar integrator (`--simd off`).
//!
//! Tolerance: none. Every lane does the scalar integrator's IEEE operations for its path and
//! each pixel sums its samples in sample order, so any difference at all is a bug (a width-
//! dependent summation order, a lane's sampler taking another lane's numbers, a stage reading a
//! neighbour's state). Agreement with the scalar integrator bit for bit is a stronger check of
//! the kernel's mean than a within-noise test: the scalar integrator is the one validated
//! against Mitsuba 3 (tests/cornell.rs, docs/validation.md).

mod common;

use common::scenes::{first_difference, job, render, scenes};
use prism::integrator::packet::{self, Simd};
use std::path::Path;

/// Every scene under scenes/ at every width this CPU runs (1 thread), at the widest on 2
/// threads, and with the scalar integrator: all the same bits. W = 16 is compiled in every
/// build; where the CPU lacks AVX-512F it is skipped with a message.
#[test]
fn every_scene_is_the_same_at_every_width_and_thread_count() {
    let widths: Vec<(Simd, usize)> = [(Simd::W1, 1), (Simd::W4, 4), (Simd::W8, 8), (Simd::W16, 16)]
        .into_iter()
        .filter(|&(_, w)| {
            let runs = packet::runs(w);
            if !runs {
                eprintln!(
                    "skipping --simd {w}: this CPU does not run it ({:?})",
                    Simd::W16.check()
                );
            }
            runs
        })
        .collect();
    assert!(widths.len() >= 2, "at least widths 1 and 4 run everywhere");
    let (mut in_packets, mut fallback, mut unloadable) = (Vec::new(), Vec::new(), Vec::new());
    for scene in scenes() {
        let Ok(reference) = job(&scene, Simd::Off) else {
            // bench/mesh.ron needs its generated mesh (tools/bench).
            unloadable.push(scene.display().to_string());
            continue;
        };
        if let Some(why) = packet::unsupported(&reference.scene, &reference.settings) {
            fallback.push(format!("{} ({why})", scene.display()));
        } else {
            in_packets.push(scene.display().to_string());
        }
        let want = render(&reference, 1);
        for &(simd, w) in &widths {
            let got = render(&job(&scene, simd).unwrap(), 1);
            if let Some(d) = first_difference(&want, &got) {
                panic!(
                    "{}: --simd {w} differs from the scalar integrator at {d}",
                    scene.display()
                );
            }
        }
        let got = render(&job(&scene, Simd::Auto).unwrap(), 2);
        if let Some(d) = first_difference(&want, &got) {
            panic!(
                "{}: --simd auto on 2 threads differs at {d}",
                scene.display()
            );
        }
    }
    eprintln!("in packets: {in_packets:?}\nscalar fallback: {fallback:?}\nnot loadable here: {unloadable:?}");
    // Guards against a silent pass: the scenes did load, and most go through the kernel.
    assert!(
        in_packets.len() >= 25,
        "only {} scenes in packets",
        in_packets.len()
    );
    assert!(unloadable.len() <= 1, "{unloadable:?}");
}

/// The fallback rule names each feature the kernel does not take.
#[test]
fn the_fallback_rule_names_what_is_not_in_packets() {
    let why = |p: &str| {
        let j = job(Path::new(p), Simd::Auto).unwrap();
        packet::unsupported(&j.scene, &j.settings)
    };
    assert_eq!(why("scenes/cornell.ron"), None);
    assert_eq!(
        why("scenes/stress/dispersive_prism.ron"),
        Some("a dispersive material")
    );
    // Caustic light tracing's camera paths are in packets (its light paths are not per pixel).
    assert_eq!(why("scenes/bench/materials.ron"), None);
    let j = job(Path::new("scenes/stress/dispersive_prism.ron"), Simd::Auto).unwrap();
    assert_eq!(packet::width(&j.scene, &j.settings), None);
}

/// Adaptive sampling in packets: its two passes (pilots, then each pixel's count from its
/// neighbours') give the scalar integrator's bits at every width and on 2 threads, the `spp`
/// and `stderr` layers included, on a 17×17 film whose corner tile is a lone pixel (its count
/// from a pilot of its own) and whose counts vary from 4 to 1024 (with the lone pixel's pilot
/// drawn from its ordinary stream instead, the corner pixel differs: value 288).
#[test]
fn adaptive_sampling_is_the_same_in_packets() {
    let load = |simd| {
        let mut j = prism::load::load(Path::new("scenes/cornell.ron"), |cfg| {
            cfg.film.width = 17;
            cfg.film.height = 17;
            cfg.aovs = vec!["stderr".into(), "spp".into()];
            cfg.sampler.spp = prism::config::Spp::Adaptive(prism::config::AdaptiveSpp {
                rel_error: 0.2,
                min: 4,
                max: 1024,
                target: Default::default(),
                floor: 1e-3,
            });
        })
        .unwrap();
        j.settings.simd = simd;
        j
    };
    let reference = load(Simd::Off);
    assert_eq!(
        packet::unsupported(&reference.scene, &reference.settings),
        None
    );
    let want = render(&reference, 1);
    let spp = &want
        .iter()
        .find(|(n, _)| n == "spp.N")
        .expect("an spp layer")
        .1;
    let (lo, hi) = (spp.iter().min().unwrap(), spp.iter().max().unwrap());
    assert!(lo < hi, "counts {lo}..{hi} should vary");
    for simd in [Simd::W1, Simd::W4, Simd::Auto] {
        let got = render(&load(simd), 1);
        if let Some(d) = first_difference(&want, &got) {
            panic!("adaptive, --simd {simd:?}: differs from the scalar integrator at {d}");
        }
    }
    let got = render(&load(Simd::Auto), 2);
    assert_eq!(first_difference(&want, &got), None, "2 threads");
}

/// `--simd` takes the width (recorded in the EXR header) and refuses one this CPU lacks with
/// exit 2 and the widths it has.
#[test]
fn the_command_line_takes_simd_and_refuses_a_width_the_cpu_lacks() {
    let dir = std::env::temp_dir().join(format!("prism_packet_cli_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let exr = dir.join("c.exr");
    let run = |simd: &str| {
        std::process::Command::new(env!("CARGO_BIN_EXE_prism"))
            .args([
                "render",
                "scenes/cornell.ron",
                "--spp",
                "1",
                "-q",
                "--simd",
                simd,
                "-o",
            ])
            .arg(&exr)
            .output()
            .unwrap()
    };
    let out = run("4");
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let header = std::fs::read(&exr).unwrap();
    let text = String::from_utf8_lossy(&header[..4096.min(header.len())]).to_string();
    assert!(
        text.contains("4 paths per packet"),
        "header lacks the width"
    );
    let _ = std::fs::remove_file(&exr);
    let lacking = [16, 8].into_iter().find(|&w| !packet::runs(w));
    if let Some(w) = lacking {
        let out = run(&w.to_string());
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{err}");
        assert!(
            err.contains("lacks") && err.contains("--simd auto"),
            "{err}"
        );
        assert!(!exr.exists(), "a refused render wrote its output");
    } else {
        eprintln!("this CPU runs every width: the refusal is not exercised here");
    }
    let out = run("5");
    assert_eq!(out.status.code(), Some(2), "--simd 5 is not a width");
    let _ = std::fs::remove_dir_all(&dir);
}
