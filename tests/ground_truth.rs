//! Ground truth layers against closed forms: depth, distance, position and normals of a sphere
//! and a tilted plane at pixel centres, computed here from the textbook pinhole (OpenCV's
//! K = [[fx, 0, cx], [0, fy, cy], [0, 0, 1]], fx = W / (2 tan(fov/2)), cx = W/2 − 0.5, and a
//! look-at R with rows right, down, forward) and ray–sphere / ray–plane intersection, not
//! from prism's camera code; AOVs identical across thread counts; bad camera and AOV input.

use glam::DVec3;
use prism::error::Error;
use prism::film::Film;
use prism::integrator;
use prism::math::portable;
use std::path::Path;

const SCENE: &str = r#"(
    camera: (fov: 50, to_world: [LookAt(origin: (0.3, 0.5, 4), target: (0, 0, 0), up: (0, 1, 0))]),
    film: (width: 64, height: 48),
    sampler: (spp: 4),
    shapes: [
        (shape: Sphere(center: (0.2, -0.1, 0), radius: 0.8), name: "ball", label: "round"),
        (shape: Rectangle, name: "board", label: "flat",
         to_world: [Scale((3, 3, 1)), Rotate(axis: (1, 0, 0), angle: -60), Translate((0, -0.5, -1))]),
    ],
    emitters: [Constant(radiance: Constant(1))],
    aovs: ["depth", "distance", "position", "normal", "geo_normal", "normal_camera", "instance", "label", "alpha"],
)"#;

fn layers(text: &str, threads: usize) -> Film {
    let job = prism::load::load_str(text, Path::new("inline.ron")).unwrap();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let mut film = integrator::render(&job.scene, &job.settings, &job.channels, &|_| {}).0;
        prism::pipeline::add_layers(&job, &mut film, None);
        film
    })
}

fn ch<'a>(f: &'a Film, name: &str) -> &'a [f32] {
    f.channel(name)
        .unwrap_or_else(|| panic!("no channel {name}"))
}

fn ids<'a>(f: &'a Film, name: &str) -> &'a [u32] {
    &f.uint_channels
        .iter()
        .find(|c| c.name == name)
        .unwrap()
        .data
}

/// The closed-form first hit of the ray from `o` along unit `d`: (t, normal, instance id).
fn analytic(o: DVec3, d: DVec3) -> Option<(f64, DVec3, u32)> {
    let mut best: Option<(f64, DVec3, u32)> = None;
    // Sphere.
    let (c, r) = (DVec3::new(0.2, -0.1, 0.0), 0.8);
    let oc = o - c;
    let b = oc.dot(d);
    let disc = b * b - (oc.length_squared() - r * r);
    if disc >= 0.0 {
        let t = -b - disc.sqrt();
        if t > 0.0 {
            best = Some((t, (o + d * t - c) / r, 1));
        }
    }
    // Rectangle [-3, 3]² rotated by −60° about x (right-handed: (0,0,1) → (0, −sin θ, cos θ)).
    let th = (-60f64).to_radians();
    let n = DVec3::new(0.0, -portable::sin(th), portable::cos(th));
    let (u, v) = (
        DVec3::X,
        DVec3::new(0.0, portable::cos(th), portable::sin(th)),
    );
    let p0 = DVec3::new(0.0, -0.5, -1.0);
    let t = (p0 - o).dot(n) / d.dot(n);
    let q = o + d * t - p0;
    if t > 0.0 && q.dot(u).abs() <= 3.0 && q.dot(v).abs() <= 3.0 && best.is_none_or(|b| t < b.0) {
        best = Some((t, n, 2));
    }
    best
}

#[test]
fn sphere_and_plane_match_closed_forms() {
    let film = layers(SCENE, 2);
    let (w, h) = (64usize, 48usize);
    let eye = DVec3::new(0.3, 0.5, 4.0);
    let fwd = (DVec3::ZERO - eye).normalize();
    let right = fwd.cross(DVec3::Y).normalize();
    let down = fwd.cross(right);
    let fx = w as f64 / (2.0 * portable::tan(25f64.to_radians()));
    let (cx, cy) = (w as f64 / 2.0 - 0.5, h as f64 / 2.0 - 0.5);
    let (mut compared, mut id_mismatch, mut full) = (0, 0, 0);
    for j in 0..h {
        for i in 0..w {
            let k = j * w + i;
            // OpenCV pixel (i, j) is prism's pixel centre (i + 0.5, j + 0.5).
            let dc = DVec3::new((i as f64 - cx) / fx, (j as f64 - cy) / fx, 1.0);
            let d = (right * dc.x + down * dc.y + fwd * dc.z).normalize();
            let id = ids(&film, "instance.ID")[k];
            let Some((t, n, want)) = analytic(eye, d) else {
                assert_eq!(id, 0, "pixel ({i}, {j}) sees nothing");
                assert_eq!(ch(&film, "depth.Z")[k], f32::INFINITY);
                assert!(ch(&film, "alpha.A")[k] < 1.0);
                continue;
            };
            if id != want {
                id_mismatch += 1;
                continue;
            }
            let cos = n.dot(d).abs();
            if cos < 0.05 {
                continue; // grazing silhouette pixels: f32 and f64 may disagree on the surface
            }
            compared += 1;
            let p = eye + d * t;
            let depth = (p - eye).dot(fwd);
            // An f32 hit ~4 units away is good to ~1e-6 relative; 2e-5·t/cos leaves margin for
            // the f32 ray direction, whose error moves the hit by ~t·1e-7/cos.
            let tol = 2e-5 * t / cos;
            assert!(
                (ch(&film, "distance.Z")[k] as f64 - t).abs() < tol,
                "distance at ({i},{j})"
            );
            assert!(
                (ch(&film, "depth.Z")[k] as f64 - depth).abs() < tol,
                "depth at ({i},{j})"
            );
            for (c, axis) in ["X", "Y", "Z"].iter().enumerate() {
                let pos = ch(&film, &format!("position.{axis}"))[k] as f64;
                assert!((pos - p[c]).abs() < tol, "position.{axis} at ({i},{j})");
                let ng = ch(&film, &format!("geo_normal.{axis}"))[k] as f64;
                let ns = ch(&film, &format!("normal.{axis}"))[k] as f64;
                assert!(
                    (ng - n[c]).abs() < 1e-4 && (ns - n[c]).abs() < 1e-4,
                    "normal.{axis} at ({i},{j}): {ns} vs {}",
                    n[c]
                );
            }
            // Camera frame (OpenCV): n_cam = (n·right, n·down, n·forward).
            let nc = DVec3::new(n.dot(right), n.dot(down), n.dot(fwd));
            for (c, axis) in ["X", "Y", "Z"].iter().enumerate() {
                let v = ch(&film, &format!("normal_camera.{axis}"))[k] as f64;
                assert!(
                    (v - nc[c]).abs() < 1e-4,
                    "normal_camera.{axis} at ({i},{j})"
                );
            }
            // Labels sort: "flat" = 1 (the board, instance 2), "round" = 2 (the ball, 1).
            assert_eq!(ids(&film, "label.ID")[k], 3 - want, "label at ({i},{j})");
            // Coverage is filtered: only pixels whose filter footprint misses no surface are 1.
            assert!(ch(&film, "alpha.A")[k] > 0.0);
            full += (ch(&film, "alpha.A")[k] == 1.0) as u32;
        }
    }
    assert!(compared > 2000, "{compared} pixels compared");
    assert!(
        full as f64 > 0.9 * compared as f64,
        "{full} of {compared} fully covered"
    );
    assert!(
        id_mismatch <= 20,
        "{id_mismatch} pixels see another object than the closed form"
    );
}

#[test]
fn aovs_identical_across_thread_counts() {
    let a = layers(SCENE, 1);
    let b = layers(SCENE, 3);
    assert_eq!(a.channels, b.channels);
    assert_eq!(a.uint_channels, b.uint_channels);
}

fn load_err(text: &str) -> prism::error::InputError {
    match prism::load::load_str(text, Path::new("bad.ron")) {
        Err(Error::Input(e)) => *e,
        Err(e) => panic!("not an input error: {e}"),
        Ok(_) => panic!("accepted"),
    }
}

#[test]
fn bad_input_names_file_field_and_fix() {
    let e = load_err(r#"(aovs: ["depth", "normals"])"#);
    assert_eq!(e.field.as_deref(), Some("aovs[1]"));
    assert!(e.hint.unwrap().contains("geo_normal_camera"));
    let e = load_err(r#"(shapes: [(shape: Sphere(), name: "a"), (shape: Cube, name: "a")])"#);
    assert_eq!(e.field.as_deref(), Some("shapes[1].name"));
    let e = load_err(
        r#"(film: (width: 320, height: 240), camera: (intrinsics: Some((fx: 200, fy: 200, cx: 159.5, cy: 119.5)), distortion: Some((k1: -0.2))))"#,
    );
    assert_eq!(e.field.as_deref(), Some("camera.distortion"));
    assert!(e.message.contains("folds"), "{}", e.message);
    let e = load_err(r#"(camera: (model: ThinLens(aperture_radius: 0.1, focus_distance: 0)))"#);
    assert_eq!(e.field.as_deref(), Some("camera.model.focus_distance"));
    let e = load_err(
        r#"(camera: (model: ThinLens(aperture_radius: 0.1, focus_distance: 2)), integrator: (caustics: Some(())))"#,
    );
    assert_eq!(e.field.as_deref(), Some("integrator.caustics"));
    let e = load_err(r#"(camera: (model: Orthographic()))"#);
    assert_eq!(e.field.as_deref(), Some("camera.model"));
}

/// A sphere of `material` in front of the constant background, with 31 bands of 10 nm.
fn albedo_film(material: &str) -> Film {
    layers(
        &format!(
            r#"(
    camera: (fov: 40, to_world: [LookAt(origin: (0, 0, 4), target: (0, 0, 0), up: (0, 1, 0))]),
    film: (width: 24, height: 16),
    sampler: (spp: 1),
    outputs: (bands: 31, band_range: (400, 710)),
    materials: {{"m": {material}}},
    shapes: [(shape: Sphere(radius: 1), material: "m")],
    emitters: [Constant(radiance: Constant(1))],
    aovs: ["depth", "albedo"],
)"#
        ),
        2,
    )
}

fn band_names(f: &Film) -> Vec<(f32, String)> {
    let names: Vec<(f32, String)> = (0..31)
        .map(|k| {
            let nm = 405.0 + 10.0 * k as f32;
            (
                nm,
                format!("albedo.{}", prism::film::spectral_channel_name(nm)),
            )
        })
        .collect();
    for (_, n) in &names {
        ch(f, n);
    }
    names
}

/// Constant ρ: every band is ρ (to f32 rounding) and R = G = B = ρ within 1e-3 (the XYZ → sRGB
/// matrix's 7-digit coefficients map D65's XYZ to white only to ~1e-4); background 0.
#[test]
fn albedo_of_constant_reflectance_is_that_reflectance() {
    let f = albedo_film("Diffuse(reflectance: Constant(0.37))");
    let depth = ch(&f, "depth.Z");
    let (mut hit, mut miss) = (0, 0);
    for (i, d) in depth.iter().enumerate() {
        let want = if d.is_finite() { 0.37 } else { 0.0 };
        for c in ["R", "G", "B"] {
            let v = ch(&f, &format!("albedo.{c}"))[i];
            assert!((v - want).abs() < 1e-3, "pixel {i} {c}: {v} vs {want}");
        }
        for (_, n) in band_names(&f) {
            assert!((ch(&f, &n)[i] - want).abs() < 1e-6, "pixel {i} {n}");
        }
        if d.is_finite() {
            hit += 1
        } else {
            miss += 1
        }
    }
    assert!(hit > 50 && miss > 50, "{hit} hits, {miss} misses");
}

/// An Rgb reflectance: the bands are the uplifted spectrum (each band's mean within 2e-3 of its
/// value at the centre: the sigmoid's curvature over 10 nm), and R/G/B give back the input
/// within 0.01 (the rgb2spec table's fit error in sRGB, well under 0.01 for mid-gamut colours).
/// A twosided material seen from outside is its front; a conductor has no diffuse albedo.
#[test]
fn albedo_of_rgb_reflectance_matches_uplift() {
    let rgb = [0.7f32, 0.4, 0.2];
    let f = albedo_film("Twosided(bsdf: Diffuse(reflectance: Rgb(0.7, 0.4, 0.2)), back: Some(Diffuse(reflectance: Constant(0.9))))");
    let curve = prism::spectrum::Curve::rgb_reflectance(rgb);
    let i = ch(&f, "depth.Z")
        .iter()
        .position(|d| d.is_finite())
        .unwrap();
    for (c, want) in ["R", "G", "B"].iter().zip(rgb) {
        let v = ch(&f, &format!("albedo.{c}"))[i];
        assert!((v - want).abs() < 0.01, "{c}: {v} vs {want}");
    }
    for (nm, n) in band_names(&f) {
        let (v, want) = (ch(&f, &n)[i], curve.eval_one(nm));
        assert!((v - want).abs() < 2e-3, "{n}: {v} vs {want}");
    }
    let f = albedo_film("Conductor(material: \"Au\")");
    assert!(ch(&f, "albedo.G").iter().all(|v| *v == 0.0));
}

#[test]
fn albedo_bad_input() {
    let e = load_err(r#"(aovs: ["albedos"])"#);
    assert_eq!(e.field.as_deref(), Some("aovs[0]"));
    assert!(e.hint.unwrap().contains("albedo"));
    let e = load_err(r#"(aovs: ["albedo", "albedo"])"#);
    assert_eq!(e.field.as_deref(), Some("aovs[1]"));
}
