//! Every material, tested through its public interface (`Material::bsdf` → `Bsdf<N>`):
//!
//! - **chi-square**: directions drawn by `sample` match `pdf`, at several incident angles (and
//!   roughnesses, where the material has one). Smooth directions are binned over the whole
//!   sphere in (1 − cos θ, φ) cells; Dirac samples form one extra cell whose expected count is
//!   n·(1 − ∫pdf). Passes if p > α = 1% / (number of chi-square tests in this file) (Šidák).
//! - **consistency**: each smooth sample's weight equals eval/pdf (relative 1e-3, f32 rounding).
//! - **reciprocity**: f(wi, wo) = f(wo, wi) for reflection (relative 1e-3).
//! - **energy (white furnace)**: the albedo E[weight] ≤ 1 everywhere; = 1 for lossless cases.
//!   Tolerance: 4 standard errors of the 100k-sample mean.

mod common;

use common::{alpha, chi2_test};
use glam::{Vec2, Vec3};
use prism::bsdf::{Bsdf, BsdfLike, Material};
use prism::interaction::SurfaceInteraction;
use prism::math::portable;
use prism::math::rng::Pcg32;
use prism::math::Frame;
use prism::spectrum::{WavelengthSampler, WavelengthSampling, Wavelengths};
use std::f64::consts::PI;
use std::path::Path;

/// Chi-square tests this file runs (for the significance level): 46 for diffuse, plastics,
/// conductors and mixtures, 44 for dielectrics (40 rough-dielectric configurations, 2
/// dispersive, 2 blended), 12 for the principled material. Counted by instrumenting `chi2_binned`.
const CHI2_TESTS: usize = 102;

/// A material from its RON config (through the scene loader, so checks apply).
pub fn material(cfg: &str) -> Material {
    let text = format!(
        "(film: (width: 2, height: 2), outputs: (bands: 0), materials: {{ \"m\": {cfg} }}, shapes: [(shape: Rectangle, material: \"m\")])"
    );
    let job = prism::load::load_str(&text, Path::new("inline.ron"))
        .unwrap_or_else(|e| panic!("{cfg}: {e}"));
    job.scene.materials[0].clone()
}

fn hit() -> SurfaceInteraction {
    SurfaceInteraction {
        p: Vec3::ZERO,
        p_error: Vec3::ZERO,
        ng: Vec3::Z,
        frame: Frame::from_normal(Vec3::Z),
        uv: Vec2::new(0.3, 0.7),
        t: 1.0,
        shape: 0,
        prim: 0,
        time: 0.0,
        bary: glam::Vec2::ZERO,
    }
}

fn wavelengths(u: f32) -> Wavelengths<4> {
    WavelengthSampler::new(WavelengthSampling::Uniform, 360.0, 830.0).sample(u)
}

fn bsdf(m: &Material, wi: Vec3) -> Bsdf<'_, 4> {
    m.bsdf(&hit(), wi, &wavelengths(0.37))
}

/// An incident direction at `theta_deg` from the normal (negative: from below).
pub fn dir(theta_deg: f32) -> Vec3 {
    let t = theta_deg.abs().to_radians();
    let z = if theta_deg < 0.0 {
        -portable::cos(t)
    } else {
        portable::cos(t)
    };
    Vec3::new(portable::sin(t) * 0.8, portable::sin(t) * 0.6, z).normalize()
}

fn u2(rng: &mut Pcg32) -> Vec2 {
    Vec2::new(rng.next_f32(), rng.next_f32())
}

/// Gauss–Legendre nodes and weights on [0, 1] (weights sum to 1): the roots of P_n by Newton's
/// method from Chebyshev starting points.
fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    (0..n)
        .map(|i| {
            let mut x = portable::cos(PI * (i as f64 + 0.75) / (n as f64 + 0.5));
            let mut dp = 1.0;
            for _ in 0..100 {
                // P_n(x) and P_n'(x) by the three-term recurrence.
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=n {
                    let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                    (p0, p1) = (p1, p2);
                }
                dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
                let dx = p1 / dp;
                x -= dx;
                if dx.abs() < 1e-15 {
                    break;
                }
            }
            ((1.0 - x) / 2.0, 1.0 / ((1.0 - x * x) * dp * dp))
        })
        .collect()
}

/// Chi-square test of `sample` against `pdf` for incident direction `wi`.
pub fn chi2(name: &str, m: &Material, wi: Vec3) {
    chi2_binned(name, m, wi, Vec3::Z, 10);
}

/// `chi2` with the sphere binned in (1 − cos θ, φ) about `pole`, each cell's expected count
/// integrated by Gauss–Legendre quadrature on `sub`×`sub` nodes. Cells near a pole are caps
/// whose nearest node row is a few degrees off the pole, so a lobe narrower than that must not
/// sit on a pole: pick a pole away from it (e.g. normal to the plane of incidence).
pub fn chi2_binned(name: &str, m: &Material, wi: Vec3, pole: Vec3, sub: usize) {
    const NT: usize = 40;
    const NP: usize = 80;
    let n = 200_000usize;
    let b = bsdf(m, wi);
    let frame = Frame::from_normal(pole.normalize());
    let mut rng = Pcg32::new(0xb5df, 3);
    let mut observed = vec![0.0; NT * NP + 1];
    let dcos = 2.0 / NT as f64;
    let dphi = 2.0 * PI / NP as f64;
    for _ in 0..n {
        let Some(s) = b.sample(wi, rng.next_f32(), u2(&mut rng)) else {
            continue;
        };
        if s.delta {
            observed[NT * NP] += 1.0;
            continue;
        }
        let w = frame.to_local(s.wo).as_dvec3().normalize();
        let it = (((1.0 - w.z) / dcos) as usize).min(NT - 1);
        let ip = ((portable::atan2(w.y, w.x).rem_euclid(2.0 * PI) / dphi) as usize).min(NP - 1);
        observed[it * NP + ip] += 1.0;
    }
    let mut expected = vec![0.0; NT * NP + 1];
    let mut total = 0.0;
    // Gauss–Legendre rather than the midpoint rule within a cell: a lobe a few hundredths of a
    // cell wide (a smooth metal seen head-on) is still integrated to ~1e-6, and any shortfall
    // would land in the Dirac cell, which such a lobe never fills.
    // With a tilted pole the surface plane, where a pdf jumps from reflection to transmission,
    // cuts cells obliquely; quadrature converges only linearly across a jump, so those cells
    // (the nodes lie on both sides) are integrated again on 4× finer nodes.
    let nodes = gauss_legendre(sub);
    let fine = gauss_legendre(4 * sub);
    let cell = |it: usize, ip: usize, nodes: &[(f64, f64)]| {
        let (mut sum, mut above, mut below) = (0.0, false, false);
        for &(xa, wa) in nodes {
            for &(xc, wc) in nodes {
                let z = 1.0 - (it as f64 + xa) * dcos;
                let phi = (ip as f64 + xc) * dphi;
                let s = (1.0 - z * z).max(0.0).sqrt();
                let local = Vec3::new(
                    (s * portable::cos(phi)) as f32,
                    (s * portable::sin(phi)) as f32,
                    z as f32,
                );
                let wo = frame.to_world(local);
                (above, below) = (above || wo.z > 0.0, below || wo.z < 0.0);
                sum += wa * wc * b.pdf(wi, wo) as f64;
            }
        }
        (sum, above && below)
    };
    for it in 0..NT {
        for ip in 0..NP {
            let (mut sum, straddles) = cell(it, ip, &nodes);
            if straddles {
                sum = cell(it, ip, &fine).0;
            }
            let e = sum * dcos * dphi * n as f64;
            expected[it * NP + ip] = e;
            total += e;
        }
    }
    // Samples the material refuses (None) are not drawn at all: scale to the accepted ones.
    let accepted: f64 = observed.iter().sum();
    let delta_expected = (accepted - total).max(0.0);
    expected[NT * NP] = delta_expected;
    let (p, stat, dof) = chi2_test(&observed, &expected);
    let a = alpha(CHI2_TESTS);
    assert!(p > a, "{name} wi={wi:?}: chi-square {stat:.1} ({dof} dof), p = {p:.2e} < {a:.1e}; delta samples {} vs expected {delta_expected:.0}", observed[NT * NP]);
}

/// Each smooth sample's weight is eval / pdf, lane by lane.
pub fn consistency(name: &str, m: &Material, wi: Vec3) {
    let b = bsdf(m, wi);
    let mut rng = Pcg32::new(7, 7);
    for _ in 0..2000 {
        let Some(s) = b.sample(wi, rng.next_f32(), u2(&mut rng)) else {
            continue;
        };
        if s.delta {
            continue;
        }
        let (f, pdf) = (b.eval(wi, s.wo), b.pdf(wi, s.wo));
        assert!(
            (pdf - s.pdf).abs() <= 1e-3 * pdf,
            "{name}: sample pdf {} vs pdf() {pdf}",
            s.pdf
        );
        for k in 0..4 {
            let expect = f[k] / pdf;
            assert!(
                (s.weight[k] - expect).abs() <= 1e-3 * expect.abs().max(1e-3),
                "{name} lane {k}: weight {} vs eval/pdf {expect}",
                s.weight[k]
            );
        }
    }
}

/// f(wi, wo) = f(wo, wi) for reflected directions (eval includes |cos θ_o|, divided out here).
pub fn reciprocity(name: &str, m: &Material) {
    let mut rng = Pcg32::new(8, 8);
    for _ in 0..500 {
        let a = prism::math::sampling::square_to_cosine_hemisphere(u2(&mut rng));
        let c = prism::math::sampling::square_to_cosine_hemisphere(u2(&mut rng));
        if a.z < 0.05 || c.z < 0.05 {
            continue;
        }
        let f1 = bsdf(m, a).eval(a, c)[0] / c.z;
        let f2 = bsdf(m, c).eval(c, a)[0] / a.z;
        assert!(
            (f1 - f2).abs() <= 1e-3 * f1.abs().max(f2.abs()).max(1e-6),
            "{name}: f({a:?}, {c:?}) = {f1} but f reversed = {f2}"
        );
    }
}

/// Albedo E[weight] of the hero lane from `wi`, with its standard error.
pub fn albedo(m: &Material, wi: Vec3) -> (f64, f64) {
    let b = bsdf(m, wi);
    let mut rng = Pcg32::new(9, 9);
    let n = 100_000;
    let (mut s1, mut s2) = (0.0, 0.0);
    for _ in 0..n {
        let w = b
            .sample(wi, rng.next_f32(), u2(&mut rng))
            .map_or(0.0, |s| s.weight[0] as f64);
        s1 += w;
        s2 += w * w;
    }
    let mean = s1 / n as f64;
    (
        mean,
        ((s2 / n as f64 - mean * mean).max(0.0) / n as f64).sqrt(),
    )
}

pub fn energy_at_most_one(name: &str, m: &Material) {
    for t in [0.0, 30.0, 60.0, 80.0, 89.0] {
        let (a, se) = albedo(m, dir(t));
        assert!(
            a <= 1.0 + 4.0 * se + 1e-6,
            "{name} θ={t}: albedo {a} ± {se} exceeds 1"
        );
    }
}

pub fn energy_is_one(name: &str, m: &Material, angles: &[f32]) {
    for &t in angles {
        let (a, se) = albedo(m, dir(t));
        assert!(
            (a - 1.0).abs() <= 4.0 * se + 1e-4,
            "{name} θ={t}: albedo {a} ± {se}, expected 1"
        );
    }
}

#[test]
fn diffuse() {
    let m = material("Diffuse(reflectance: Constant(0.8))");
    for t in [0.0, 45.0, 85.0] {
        chi2("diffuse", &m, dir(t));
        consistency("diffuse", &m, dir(t));
    }
    reciprocity("diffuse", &m);
    energy_at_most_one("diffuse", &m);
    // Albedo of a Lambertian surface is its reflectance.
    let (a, se) = albedo(&m, dir(40.0));
    assert!((a - 0.8).abs() <= 4.0 * se + 1e-6, "{a}");
    assert!(
        bsdf(&m, dir(-40.0))
            .sample(dir(-40.0), 0.5, Vec2::splat(0.5))
            .is_none(),
        "one-sided"
    );
}

#[test]
fn twosided_mirrors_the_back() {
    let m = material("Twosided(bsdf: Diffuse(reflectance: Constant(0.6)))");
    for t in [30.0, -30.0, -80.0] {
        chi2("twosided", &m, dir(t));
        consistency("twosided", &m, dir(t));
    }
    let (a, se) = albedo(&m, dir(-50.0));
    assert!((a - 0.6).abs() <= 4.0 * se + 1e-6, "back side albedo {a}");
    // Different BSDFs per side.
    let m = material("Twosided(bsdf: Diffuse(reflectance: Constant(0.2)), back: Diffuse(reflectance: Constant(0.9)))");
    assert!(
        (albedo(&m, dir(20.0)).0 - 0.2).abs() < 0.01
            && (albedo(&m, dir(-20.0)).0 - 0.9).abs() < 0.01
    );
}

#[test]
fn blend_and_mask() {
    let blend = material("Blend(weight: 0.25, bsdf0: Diffuse(reflectance: Constant(0.8)), bsdf1: Mask(opacity: 0.5, bsdf: Diffuse(reflectance: Constant(0.4))))");
    for t in [10.0, 70.0] {
        chi2("blend+mask", &blend, dir(t));
        consistency("blend+mask", &blend, dir(t));
    }
    // 0.75·0.8 + 0.25·(0.5·0.4 + 0.5·1 (pass-through)) = 0.6 + 0.175.
    let (a, se) = albedo(&blend, dir(30.0));
    assert!((a - 0.775).abs() <= 4.0 * se + 1e-6, "blend albedo {a}");
    let mask = material("Mask(opacity: 0.0, bsdf: Diffuse())");
    energy_is_one("fully transparent mask", &mask, &[0.0, 60.0, -60.0]);
}

#[test]
fn plastic() {
    let m = material("Plastic(diffuse_reflectance: Constant(0.5))");
    for t in [0.0, 45.0, 80.0] {
        chi2("plastic", &m, dir(t));
        consistency("plastic", &m, dir(t));
    }
    reciprocity("plastic", &m);
    // Albedo = F(θi) + (1 − F(θi))·ρ exactly: internal reflections are folded in with the
    // hemispherical Fresnel averages, and 1 − F̄_int = (1 − F̄_ext)/η².
    for t in [0.0f32, 50.0, 80.0] {
        let eta = 1.49 / 1.000_277;
        let f = prism::bsdf::fresnel::dielectric(dir(t).z, eta).0 as f64;
        let (a, se) = albedo(&m, dir(t));
        let expect = f + (1.0 - f) * 0.5;
        assert!(
            (a - expect).abs() <= 4.0 * se + 1e-3,
            "θ={t}: albedo {a} ± {se}, expected {expect}"
        );
    }
    let white = material("Plastic(diffuse_reflectance: Constant(1.0))");
    energy_is_one("white plastic", &white, &[0.0, 40.0, 75.0]);
    let nonlinear = material("Plastic(diffuse_reflectance: Constant(0.9), nonlinear: true)");
    energy_at_most_one("nonlinear plastic", &nonlinear);
}

#[test]
fn rough_plastic() {
    for dist in ["Beckmann", "Ggx"] {
        for alpha in [0.1, 0.4] {
            let m = material(&format!("RoughPlastic(distribution: {dist}, alpha: {alpha}, diffuse_reflectance: Rgb(0.7, 0.3, 0.2))"));
            let name = format!("roughplastic {dist} α={alpha}");
            for t in [0.0, 60.0] {
                chi2(&name, &m, dir(t));
                consistency(&name, &m, dir(t));
            }
            reciprocity(&name, &m);
            energy_at_most_one(&name, &m);
        }
    }
    // With a white base and low roughness the model is close to lossless (the single-scattering
    // microfacet coating loses a little at grazing angles).
    let m = material("RoughPlastic(alpha: 0.05, diffuse_reflectance: Constant(1.0))");
    let (a, se) = albedo(&m, dir(0.0));
    assert!(a <= 1.0 + 4.0 * se && a > 0.97, "albedo {a}");
}

/// The rough conductors under test: both distributions at three roughnesses, and an
/// anisotropic one (sampling does not depend on η, κ, so one metal serves).
fn rough_conductors() -> Vec<String> {
    let mut cfgs = Vec::new();
    for dist in ["Beckmann", "Ggx"] {
        for alpha in [0.05, 0.2, 0.6] {
            cfgs.push(format!(
                "RoughConductor(distribution: {dist}, alpha: {alpha}, material: \"Cu\")"
            ));
        }
        cfgs.push(format!(
            "RoughConductor(distribution: {dist}, alpha_u: 0.1, alpha_v: 0.4, material: \"Cu\")"
        ));
    }
    cfgs
}

#[test]
fn rough_conductor_sampling_matches_pdf() {
    for cfg in rough_conductors() {
        let m = material(&cfg);
        for t in [0.0, 45.0, 75.0] {
            chi2(&cfg, &m, dir(t));
            consistency(&cfg, &m, dir(t));
        }
    }
}

#[test]
fn rough_conductor_reciprocity_and_one_side() {
    for cfg in rough_conductors() {
        let m = material(&cfg);
        reciprocity(&cfg, &m);
        // Black from below, as Mitsuba's: no samples, no value, no density.
        let (below, above) = (dir(-40.0), dir(30.0));
        let b = bsdf(&m, below);
        assert!(b.sample(below, 0.5, Vec2::splat(0.5)).is_none(), "{cfg}");
        assert!(b.eval(below, above).is_zero() && b.pdf(below, above) == 0.0);
        let b = bsdf(&m, above);
        assert!(b.eval(above, below).is_zero() && b.pdf(above, below) == 0.0);
    }
}

/// The white furnace. A rough conductor loses the light that would scatter between microfacets
/// more than once, or leave below the horizon (the model is single-scattering), so its albedo is
/// ≤ 1 and falls with roughness. With F ≡ 1 (η = 0, κ = 1, the default), at normal incidence:
/// Beckmann 1.000 (α 0.05), 1.000 (0.2), 0.856 (0.6); GGX 0.997, 0.948, 0.592 (its long tails
/// send more facets past 45°); Mitsuba 3.9.1 gives the same to within its Monte Carlo error.
/// α = 0.05 must stay within 1% of 1.
#[test]
fn rough_conductor_energy() {
    for cfg in rough_conductors() {
        energy_at_most_one(&cfg, &material(&cfg));
    }
    for dist in ["Beckmann", "Ggx"] {
        let m = material(&format!(
            "RoughConductor(distribution: {dist}, alpha: 0.05)"
        ));
        let (a, se) = albedo(&m, dir(0.0));
        assert!(
            a <= 1.0 + 4.0 * se && a > 0.99,
            "{dist} α = 0.05: albedo {a} ± {se}"
        );
        let rough_mirror = material(&format!("RoughConductor(distribution: {dist}, alpha: 0.6)"));
        energy_at_most_one(dist, &rough_mirror);
    }
}

#[test]
fn smooth_conductor() {
    // η = 0, κ = 1 makes F = 1 at every angle (fresnel::conductor: a = 0, so r_s = r_p = 1): a
    // perfect mirror, Mitsuba's default. Every weight is exactly 1.
    for cfg in ["Conductor(eta: Constant(0), k: Constant(1))", "Conductor()"] {
        let m = material(cfg);
        energy_is_one(cfg, &m, &[0.0, 30.0, 60.0, 89.0]);
        chi2(cfg, &m, dir(40.0));
    }
    let m = material("Conductor(material: \"Au\")");
    let wi = dir(35.0);
    let b = bsdf(&m, wi);
    let s = b.sample(wi, 0.3, Vec2::new(0.1, 0.9)).unwrap();
    assert!(s.delta && s.pdf == 1.0 && s.pdf_lanes.0.iter().all(|&p| p == 1.0));
    assert!(
        (s.wo - Vec3::new(-wi.x, -wi.y, wi.z)).length() < 1e-6,
        "mirror direction"
    );
    // The weight is F(cos θ_i) per lane, below 1 for gold, and the Dirac lobe has no density.
    let wl = wavelengths(0.37);
    let (eta, k) = prism::spectrum::metals::named_metal("Au").unwrap();
    for i in 0..4 {
        let f = prism::bsdf::fresnel::conductor(
            wi.z,
            eta.eval_one(wl.lambda[i]),
            k.eval_one(wl.lambda[i]),
        );
        assert!(
            (s.weight[i] - f).abs() < 1e-6 && f < 1.0,
            "lane {i}: {} vs {f}",
            s.weight[i]
        );
    }
    assert!(b.eval(wi, s.wo).is_zero() && b.pdf(wi, s.wo) == 0.0 && !b.has_smooth());
    assert!(
        bsdf(&m, dir(-35.0))
            .sample(dir(-35.0), 0.5, Vec2::splat(0.5))
            .is_none(),
        "one-sided"
    );
    // Blended with a rough lobe, the Dirac part is drawn with its weight (the chi-square's
    // Dirac cell) and the rest follows the rough lobe's density.
    let mix =
        "Blend(weight: 0.4, bsdf0: Conductor(material: \"Au\"), bsdf1: RoughConductor(alpha: 0.3))";
    let m = material(mix);
    chi2(mix, &m, dir(30.0));
    consistency(mix, &m, dir(30.0));
    energy_at_most_one(mix, &m);
    // specular_reflectance scales the reflection (exactly: the mirror's F is 1).
    let half = material("Conductor(specular_reflectance: Constant(0.5))");
    let (a, _) = albedo(&half, dir(20.0));
    assert!((a - 0.5).abs() < 1e-6, "{a}");
}

/// eval and pdf agree with Mitsuba 3.9.1's `roughconductor` (scalar_spectral, `bsdf.eval` and
/// `bsdf.pdf`, printed by tools/reference/roughconductor_reference.py, at λ = 450, 550, 650, 700 nm, wi ∝ (0.3, −0.2, 0.9), wo ∝ (−0.5, 0.1, 0.7)): the
/// metal data, the Fresnel term and the microfacet model together. Mitsuba prints 6 digits and
/// both compute in f32: relative 1e-4.
#[test]
fn rough_conductor_matches_mitsuba() {
    let wl = Wavelengths {
        lambda: [450.0, 550.0, 650.0, 700.0],
        pdf: [1.0; 4],
    };
    let wi = Vec3::new(0.3, -0.2, 0.9).normalize();
    let wo = Vec3::new(-0.5, 0.1, 0.7).normalize();
    let cases = [
        (
            "RoughConductor(material: \"Au\", alpha: 0.3)",
            [0.288992, 0.633063, 0.702437, 0.719106],
            0.747_410_95,
        ),
        (
            "RoughConductor(material: \"Cu\", distribution: Ggx, alpha_u: 0.2, alpha_v: 0.5)",
            [0.191488, 0.219661, 0.326059, 0.330606],
            0.348_775_77,
        ),
        (
            "RoughConductor(material: \"Cr\", distribution: Ggx, alpha: 0.4)",
            [0.283714, 0.265809, 0.258792, 0.257808],
            0.412_747_77,
        ),
    ];
    for (cfg, f, pdf) in cases {
        let m = material(cfg);
        let b: Bsdf<4> = m.bsdf(&hit(), wi, &wl);
        let (ours, our_pdf) = (b.eval(wi, wo), b.pdf(wi, wo));
        for i in 0..4 {
            assert!(
                (ours[i] - f[i]).abs() <= 1e-4 * f[i],
                "{cfg} at {} nm: {} vs Mitsuba {}",
                wl.lambda[i],
                ours[i],
                f[i]
            );
        }
        assert!(
            (our_pdf - pdf).abs() <= 1e-4 * pdf,
            "{cfg}: pdf {our_pdf} vs Mitsuba {pdf}"
        );
    }
}

/// The albedos themselves, not only "at most 1": the directional albedo E[weight] of prism's
/// sampling against Mitsuba 3.9.1's (tools/reference/albedo_reference.py: 200 000 samples of
/// its `bsdf.sample` at 550 nm, same wi), for the rough conductors with F ≡ 1 (the
/// single-scattering energy loss of each microfacet model) and two rough plastics. Tolerance:
/// 4 combined standard errors, plus 1e-4 (the models agree to 1e-4 in `eval`) for the
/// conductors and 0.3% for the plastics (as rough_plastic_matches_mitsuba: both tabulate the
/// coating's transmittance, differently).
#[test]
fn albedos_match_mitsuba() {
    /// (θi in degrees, Mitsuba's albedo, its standard error).
    type Albedo = (f32, f64, f64);
    #[rustfmt::skip]
    const MITSUBA: [(&str, [Albedo; 3]); 8] = [
        (r#"RoughConductor(distribution: Beckmann, alpha: 0.05)"#, [(0.0, 1.00000, 0.00000), (60.0, 1.00000, 0.00000), (80.0, 0.99347, 0.00015)]),
        (r#"RoughConductor(distribution: Beckmann, alpha: 0.2)"#, [(0.0, 1.00000, 0.00000), (60.0, 0.97257, 0.00031), (80.0, 0.90815, 0.00054)]),
        (r#"RoughConductor(distribution: Beckmann, alpha: 0.6)"#, [(0.0, 0.85609, 0.00063), (60.0, 0.85257, 0.00066), (80.0, 0.91750, 0.00044)]),
        (r#"RoughConductor(distribution: Ggx, alpha: 0.05)"#, [(0.0, 0.99727, 0.00011), (60.0, 0.99253, 0.00015), (80.0, 0.95292, 0.00032)]),
        (r#"RoughConductor(distribution: Ggx, alpha: 0.2)"#, [(0.0, 0.94732, 0.00045), (60.0, 0.89425, 0.00053), (80.0, 0.84918, 0.00056)]),
        (r#"RoughConductor(distribution: Ggx, alpha: 0.6)"#, [(0.0, 0.59162, 0.00091), (60.0, 0.62421, 0.00084), (80.0, 0.70197, 0.00071)]),
        (r#"RoughPlastic(distribution: Ggx, alpha: 0.1, diffuse_reflectance: Constant(0.5))"#, [(0.0, 0.47429, 0.00009), (60.0, 0.49640, 0.00013), (80.0, 0.56527, 0.00030)]),
        (r#"RoughPlastic(distribution: Ggx, alpha: 0.4, diffuse_reflectance: Constant(0.5))"#, [(0.0, 0.32106, 0.00010), (60.0, 0.31498, 0.00014), (80.0, 0.31198, 0.00017)]),
    ];
    for (cfg, rows) in MITSUBA {
        let m = material(cfg);
        let model = if cfg.starts_with("RoughPlastic") {
            3e-3
        } else {
            1e-4
        };
        for (theta, want, want_se) in rows {
            let (got, se) = albedo(&m, dir(theta));
            let tol = 4.0 * (se * se + want_se * want_se).sqrt() + model * want;
            println!("{cfg} θ={theta}: prism {got:.5} ± {se:.5}, Mitsuba {want:.5} ± {want_se:.5}");
            assert!(
                (got - want).abs() <= tol,
                "{cfg} θ={theta}: albedo {got} ± {se}, Mitsuba {want} ± {want_se} (tolerance {tol})"
            );
        }
    }
}

// Dielectrics.

/// An interface with relative index `eta_case` ("1.5": glass outside air; "1/1.33": air
/// bubble in water, i.e. the denser medium outside).
fn iors(eta_case: &str) -> &'static str {
    match eta_case {
        "1.5" => "int_ior: 1.5, ext_ior: 1.0",
        "1/1.33" => "int_ior: 1.0, ext_ior: 1.33",
        _ => unreachable!(),
    }
}

/// Energy of the hero lane from `wi` with the radiance scaling undone: E[weight · η²], where
/// a sample's η is the relative index it crossed (1 for reflection). Radiance is compressed by
/// 1/η² when it crosses into a denser medium, so E[weight] itself may exceed 1 from inside
/// glass; the energy (flux) fraction E[weight · η²] may not. Returns (mean, standard error).
fn energy(m: &Material, wi: Vec3) -> (f64, f64) {
    let b = bsdf(m, wi);
    let mut rng = Pcg32::new(9, 9);
    let n = 100_000;
    let (mut s1, mut s2) = (0.0, 0.0);
    for _ in 0..n {
        let w = b
            .sample(wi, rng.next_f32(), u2(&mut rng))
            .map_or(0.0, |s| (s.weight[0] * s.eta * s.eta) as f64);
        s1 += w;
        s2 += w * w;
    }
    let mean = s1 / n as f64;
    (
        mean,
        ((s2 / n as f64 - mean * mean).max(0.0) / n as f64).sqrt(),
    )
}

/// `chi2` for glossy lobes: reflection and refraction peak in the plane of incidence (which
/// `dir` puts at azimuth atan2(0.6, 0.8)), so the bins' pole is the normal to that plane, and
/// cells are integrated on 20×20 nodes (a cell spans ~3°×4.5°; α = 0.1 lobes are a few
/// degrees wide, and refraction near the critical angle folds them more sharply still).
fn chi2_glossy(name: &str, m: &Material, wi: Vec3) {
    chi2_binned(name, m, wi, Vec3::new(-0.6, 0.8, 0.0), 20);
}

/// Chi-square of the rough dielectric's sampling against its pdf for both distributions, two
/// roughnesses, glass (η = 1.5) and an air bubble in water (η = 1/1.33), from outside and from
/// inside (negative angles); the refractions land in the lower hemisphere, which the binning
/// covers (the whole sphere). Also: each sample's weight is eval/pdf lane by lane.
#[test]
fn rough_dielectric_sampling_matches_pdf() {
    for dist in ["Beckmann", "Ggx"] {
        for a in [0.1, 0.3] {
            for eta in ["1.5", "1/1.33"] {
                let cfg = format!(
                    "RoughDielectric(distribution: {dist}, alpha: {a}, {})",
                    iors(eta)
                );
                let m = material(&cfg);
                for t in [0.0, 45.0, 80.0, -30.0, -70.0] {
                    chi2_glossy(&format!("{cfg} θ={t}"), &m, dir(t));
                    consistency(&cfg, &m, dir(t));
                }
            }
        }
    }
}

/// A dispersive rough glass samples with the hero's η; its pdf is the hero's too. And a rough
/// dielectric blended with a diffuse lobe (mixture sampling of smooth lobes).
#[test]
fn rough_dielectric_dispersive_and_blended() {
    let sf11 = material("RoughDielectric(distribution: Ggx, alpha: 0.1, int_ior: Glass(\"SF11\"))");
    for t in [45.0, -30.0] {
        chi2_glossy("SF11", &sf11, dir(t));
        consistency("SF11", &sf11, dir(t));
    }
    let blend = material(
        "Blend(weight: 0.5, bsdf0: Diffuse(reflectance: Constant(0.7)), bsdf1: RoughDielectric(alpha: 0.2))",
    );
    for t in [20.0, 70.0] {
        chi2_glossy("blend", &blend, dir(t));
        consistency("blend", &blend, dir(t));
    }
}

/// For lane k, `pdf_lanes` is the density with which the material, driven by lane k's η, would
/// have sampled wo: it equals the hero pdf of a non-dispersive glass whose η is lane k's.
/// Checked for reflection and refraction from both sides. Tolerance: relative 1e-4 (the same
/// f32 expressions; η_k is rebuilt bit for bit, so only the order of operations differs).
#[test]
fn rough_dielectric_lane_densities() {
    let glass = prism::spectrum::Ior::glass("SF11").unwrap();
    let air = 1.000277f32;
    let wl = wavelengths(0.37);
    let m = material("RoughDielectric(distribution: Beckmann, alpha: 0.08, int_ior: Glass(\"SF11\"), ext_ior: 1.000277)");
    let lane_materials: Vec<Material> = (0..4)
        .map(|k| {
            material(&format!(
                "RoughDielectric(distribution: Beckmann, alpha: 0.08, int_ior: {:?}, ext_ior: {air:?})",
                glass.eval_one(wl.lambda[k])
            ))
        })
        .collect();
    let mut rng = Pcg32::new(11, 2);
    let mut checked = [0usize; 2];
    for t in [10.0, 50.0, -20.0, -40.0] {
        let wi = dir(t);
        let b = bsdf(&m, wi);
        for _ in 0..3000 {
            let Some(s) = b.sample(wi, rng.next_f32(), u2(&mut rng)) else {
                continue;
            };
            let lanes = b.pdf_lanes(wi, s.wo);
            assert!((lanes[0] - s.pdf).abs() <= 1e-4 * s.pdf, "hero lane");
            for k in 0..4 {
                assert!((s.pdf_lanes[k] - lanes[k]).abs() <= 1e-4 * lanes[k].max(1e-6));
                let single = bsdf(&lane_materials[k], wi).pdf(wi, s.wo);
                assert!(
                    (lanes[k] - single).abs() <= 1e-4 * single.max(1e-6),
                    "θ={t} lane {k}: pdf_lanes {} vs lane-η pdf {single}",
                    lanes[k]
                );
            }
            checked[(s.wo.z * wi.z < 0.0) as usize] += 1;
        }
    }
    // Both kinds of event were exercised, and secondary lanes of a refraction differ from the
    // hero (else the test would not test dispersion).
    assert!(checked[0] > 100 && checked[1] > 1000, "{checked:?}");
}

/// Reciprocity in radiance mode. Reflection: f(wi, wo) = f(wo, wi). Refraction: the physical
/// BTDF obeys f_s(in → out)/n_out² = f_s(out → in)/n_in² (Veach 1997, §5.2); our f(wi, wo) is
/// f_s(wo → wi) (light arrives along wo and leaves towards the camera along wi), so
/// f(wi, wo)/n(wi)² = f(wo, wi)/n(wo)², n(·) the index on that direction's side. Checked for
/// every lane of a dispersive glass (each with its own η). Tolerance: relative 1e-3 (f32), plus
/// 1e-6 absolute where f ≪ 1; pairs whose facet is within ~3° of grazing are skipped (f32
/// cancellation in Snell's law at the critical angle, 1% there, not a property of the model).
#[test]
fn rough_dielectric_reciprocity() {
    for cfg in [
        "RoughDielectric(distribution: Ggx, alpha: 0.3, int_ior: 1.5, ext_ior: 1.0)",
        "RoughDielectric(distribution: Beckmann, alpha: 0.2, int_ior: Glass(\"SF11\"), ext_ior: 1.0)",
    ] {
        let m = material(cfg);
        let wl = wavelengths(0.37);
        let eta: Vec<f32> = (0..4)
            .map(|k| match cfg.contains("SF11") {
                true => prism::spectrum::Ior::glass("SF11")
                    .unwrap()
                    .eval_one(wl.lambda[k]),
                false => 1.5,
            })
            .collect();
        let mut rng = Pcg32::new(8, 9);
        let mut tested = 0;
        for _ in 0..3000 {
            let a = prism::math::sampling::square_to_uniform_sphere(u2(&mut rng));
            let c = prism::math::sampling::square_to_uniform_sphere(u2(&mut rng));
            if a.z.abs() < 0.05 || c.z.abs() < 0.05 {
                continue;
            }
            let f1 = bsdf(&m, a).eval(a, c) / c.z.abs();
            let f2 = bsdf(&m, c).eval(c, a) / a.z.abs();
            for k in 0..4 {
                let n = |w: Vec3| if w.z > 0.0 { 1.0 } else { eta[k] };
                // Near the critical angle (a facet seen at grazing from the thin side) Snell's
                // cos θ_t cancels catastrophically in f32; f64 shows exact reciprocity there.
                let h = if a.z * c.z > 0.0 { a + c } else { a * n(a) + c * n(c) };
                let mh = h.normalize();
                if a.dot(mh).abs() < 0.05 || c.dot(mh).abs() < 0.05 {
                    continue;
                }
                let (l, r) = (f1[k] / (n(a) * n(a)), f2[k] / (n(c) * n(c)));
                // f32 cancellation in wo·m near grazing facets blurs tiny values: 1e-6 absolute.
                assert!(
                    (l - r).abs() <= 1e-3 * l.abs().max(r.abs()) + 1e-6,
                    "{cfg} lane {k}: f({a:?}, {c:?})/n² = {l}, reversed {r}"
                );
                tested += (l > 1e-3) as usize;
            }
        }
        assert!(tested > 500, "{cfg}: only {tested} non-zero values");
    }
}

/// White furnace. A smooth dielectric and a thin dielectric with unit specular factors lose
/// nothing: every sample's energy weight is exactly 1 (so the mean is 1 to rounding, 1e-5). A
/// rough dielectric may lose energy (single-scattering microfacets), never gain it: at most 1
/// plus 4 standard errors. Angles include the inside, beyond the critical angle.
#[test]
fn dielectric_energy() {
    for cfg in [
        "Dielectric()",
        "Dielectric(int_ior: Glass(\"SF11\"))",
        "Dielectric(int_ior: \"water\", ext_ior: Named(\"diamond\"))",
    ] {
        let m = material(cfg);
        for t in [0.0, 30.0, 60.0, 89.0, -20.0, -45.0, -80.0] {
            let (e, _) = energy(&m, dir(t));
            assert!((e - 1.0).abs() < 1e-5, "{cfg} θ={t}: energy {e}");
        }
    }
    for cfg in ["ThinDielectric()", "ThinDielectric(int_ior: Glass(\"F2\"))"] {
        energy_is_one(cfg, &material(cfg), &[0.0, 40.0, 85.0, -10.0, -70.0]);
    }
    for dist in ["Beckmann", "Ggx"] {
        for a in [0.05, 0.3, 0.8] {
            for eta in ["1.5", "1/1.33"] {
                let cfg = format!(
                    "RoughDielectric(distribution: {dist}, alpha: {a}, {})",
                    iors(eta)
                );
                let m = material(&cfg);
                for t in [0.0, 30.0, 60.0, 85.0, -30.0, -60.0, -85.0] {
                    let (e, se) = energy(&m, dir(t));
                    assert!(e <= 1.0 + 4.0 * se + 1e-6, "{cfg} θ={t}: energy {e} ± {se}");
                    // Low roughness loses little (masking only grows at grazing angles).
                    if a == 0.05 && t.abs() <= 30.0 {
                        assert!(e > 0.97, "{cfg} θ={t}: energy {e}");
                    }
                }
            }
        }
    }
}

/// The smooth dispersive dielectric through the material loader: a Sellmeier glass's lanes
/// each have their η; a reflection keeps all four lanes with pdf_lanes = F_k (lane k's
/// probability of choosing it) and weight F_k/F_hero; a refraction keeps only the hero. The
/// BSDF reports itself dispersive, a constant-IOR glass does not.
#[test]
fn smooth_dispersive_dielectric_lanes() {
    let m = material("Dielectric(int_ior: Glass(\"BK7\"), ext_ior: Named(\"vacuum\"))");
    let wl = wavelengths(0.37);
    let bk7 = prism::spectrum::Ior::glass("BK7").unwrap();
    let wi = dir(55.0);
    let b = bsdf(&m, wi);
    assert!(b.dispersive() && !b.has_smooth());
    let f: Vec<f32> = (0..4)
        .map(|k| prism::bsdf::fresnel::dielectric(wi.z, bk7.eval_one(wl.lambda[k])).0)
        .collect();
    assert!(
        f.windows(2).all(|w| w[0] != w[1]),
        "lanes must differ: {f:?}"
    );
    let r = b.sample(wi, 0.0, Vec2::ZERO).unwrap();
    assert!(r.delta && r.wo.z > 0.0);
    for k in 0..4 {
        assert!((r.pdf_lanes[k] - f[k]).abs() < 1e-6, "lane {k}");
        assert!((r.weight[k] - f[k] / f[0]).abs() < 1e-5, "lane {k}");
    }
    let t = b.sample(wi, 0.99, Vec2::ZERO).unwrap();
    let n0 = bk7.eval_one(wl.lambda[0]);
    assert!(t.wo.z < 0.0 && (t.eta - n0).abs() < 1e-6);
    assert!((t.pdf_lanes[0] - (1.0 - f[0])).abs() < 1e-6);
    assert!((t.weight[0] - 1.0 / (n0 * n0)).abs() < 1e-5);
    for k in 1..4 {
        assert_eq!((t.pdf_lanes[k], t.weight[k]), (0.0, 0.0), "lane {k}");
    }
    let plain = material("Dielectric(int_ior: 1.5)");
    assert!(!bsdf(&plain, wi).dispersive());
    let rough = material("RoughDielectric(int_ior: Glass(\"BK7\"))");
    assert!(bsdf(&rough, wi).dispersive());
    let thin = material("ThinDielectric(int_ior: Named(\"water\"))");
    assert!(!bsdf(&thin, wi).dispersive());
}

/// Mitsuba 3.9.1's roughplastic at matched settings (GGX α 0.2, indices 1.49 / 1.000277,
/// diffuse 0.5, specular 0 and 1), f·cos θo at 550 nm, from
/// tools/reference/roughplastic_reference.py. Pins the model, not only its self-consistency:
/// the coating's transmittance table (light refracted and not masked on the way out) and its
/// internal reflectance (Mitsuba's 64-point average). Tolerance 0.3%: both sides tabulate the
/// transmittance over 64 values of cos θ and integrate it numerically in different ways.
#[test]
fn rough_plastic_matches_mitsuba() {
    const MITSUBA: [(f32, f32, [f32; 4]); 6] = [
        (0.0, 0.0, [0.126744, 0.109187, 0.059527, 0.01725]),
        (0.0, 40.0, [0.125118, 0.107787, 0.058763, 0.017029]),
        (0.0, 70.0, [0.111382, 0.095953, 0.052312, 0.015159]),
        (1.0, 0.0, [0.203681, 0.120487, 0.061111, 0.017839]),
        (1.0, 40.0, [0.132045, 0.117532, 0.061432, 0.018069]),
        (1.0, 70.0, [0.114244, 0.100329, 0.054525, 0.016236]),
    ];
    let wl = wavelengths(0.37); // the material does not vary with wavelength
    for (spec, ti, expect) in MITSUBA {
        let m = material(&format!(
            "RoughPlastic(distribution: Ggx, alpha: 0.2, diffuse_reflectance: Constant(0.5), specular_reflectance: Constant({spec:.1}))"
        ));
        let t = ti.to_radians();
        let wi = Vec3::new(portable::sin(t), 0.0, portable::cos(t));
        let b: Bsdf<4> = m.bsdf(&hit(), wi, &wl);
        for (to, want) in [0.0f32, 30.0, 60.0, 80.0].iter().zip(expect) {
            let s = portable::sin(to.to_radians());
            let wo = Vec3::new(-0.6 * s, 0.8 * s, portable::cos(to.to_radians()));
            let got = b.eval(wi, wo)[0];
            assert!(
                (got - want).abs() <= 3e-3 * want,
                "specular {spec}, θi {ti}, θo {to}: prism {got}, Mitsuba {want}"
            );
        }
    }
}

/// The glTF metallic-roughness material (`Principled`) at metallic 0, ½ and 1, three
/// roughnesses, with and without thin-walled transmission, from above and below (the material
/// is the same from both sides): 4 configurations × 3 angles = 12 chi-square tests.
fn principled_cases() -> Vec<String> {
    vec![
        "Principled(base_color: Rgb(0.8, 0.4, 0.2), metallic: 0, roughness: 0.5)".into(),
        "Principled(base_color: Rgb(0.9, 0.6, 0.3), metallic: 1, roughness: 0.3)".into(),
        "Principled(base_color: Constant(0.7), metallic: 0.5, roughness: 0.8, ior: 1.8)".into(),
        "Principled(base_color: Constant(0.9), metallic: 0.2, roughness: 0.4, transmission: 0.6, specular: 0.7)".into(),
    ]
}

#[test]
fn principled_sampling_matches_pdf() {
    for cfg in principled_cases() {
        let m = material(&cfg);
        for t in [0.0, 60.0, -35.0] {
            chi2(&cfg, &m, dir(t));
            consistency(&cfg, &m, dir(t));
        }
    }
}

/// f(wi, wo) = f(wo, wi) for reflection and for (thin-walled) transmission, and energy ≤ 1
/// (4 standard errors) at every tested angle, up to a white base colour.
#[test]
fn principled_reciprocity_and_energy() {
    for cfg in principled_cases() {
        let m = material(&cfg);
        reciprocity(&cfg, &m);
        energy_at_most_one(&cfg, &m);
        let mut rng = Pcg32::new(10, 10);
        for _ in 0..300 {
            let a = prism::math::sampling::square_to_cosine_hemisphere(u2(&mut rng));
            let mut c = prism::math::sampling::square_to_cosine_hemisphere(u2(&mut rng));
            c.z = -c.z;
            if a.z < 0.05 || c.z > -0.05 {
                continue;
            }
            let f1 = bsdf(&m, a).eval(a, c)[0] / c.z.abs();
            let f2 = bsdf(&m, c).eval(c, a)[0] / a.z;
            assert!(
                (f1 - f2).abs() <= 1e-3 * f1.abs().max(f2.abs()).max(1e-6),
                "{cfg}: transmission f({a:?}, {c:?}) = {f1}, reversed {f2}"
            );
        }
    }
    // White furnace with a white base colour. Metals (single-scattering GGX) stay below 1 at
    // every angle. The specification's dielectric does not: its diffuse base is weighted by
    // 1 − Fr(V·H) per microfacet, not by the specular layer's albedo, so towards grazing
    // incidence it gains energy (measured here at roughness 0.3: 1.025 at 60°, 1.22 at 80°,
    // 1.33 at 89°; the numpy reference of tools/tests/test_principled.py has the same values
    // pointwise). That is the spec's model, kept exactly; ≤ 1 is asserted up to 30°.
    for cfg in [
        "Principled(base_color: Constant(1), metallic: 1, roughness: 0.1)",
        "Principled(base_color: Constant(1), metallic: 1, roughness: 1)",
    ] {
        energy_at_most_one(cfg, &material(cfg));
    }
    for cfg in [
        "Principled(base_color: Constant(1), metallic: 0, roughness: 0.3)",
        "Principled(base_color: Constant(1), metallic: 0, roughness: 1)",
        "Principled(base_color: Constant(1), metallic: 0, roughness: 0.5, transmission: 1)",
    ] {
        let m = material(cfg);
        for t in [0.0, 30.0] {
            let (a, se) = albedo(&m, dir(t));
            assert!(
                a <= 1.0 + 4.0 * se + 1e-6,
                "{cfg} θ={t}: albedo {a} ± {se} exceeds 1"
            );
        }
    }
}
