//! An RGB environment map past 830 nm: its radiance is RGB × D65, and the D65 table ends at
//! 830 nm; past it prism continues D65 as a 6504 K blackbody scaled to meet it (a chosen tail,
//! documented in scenes/README.md) instead of 0, so a NIR render under an HDRI is not black.

use prism::spectrum::curve::planck;
use prism::spectrum::data::named_illuminant;
use std::path::Path;

/// The tail meets the table: the same bits inside 300–830 nm, the blackbody's shape past it
/// (relative 1e-5: the ratio is of two f32 planck values and one f32 multiply), 0 past 2500.
#[test]
fn the_envmap_illuminant_continues_d65_as_a_blackbody() {
    let d65 = named_illuminant("D65").unwrap();
    let ext = prism::emitter::envmap_illuminant();
    for l in [300.0f32, 412.3, 555.0, 700.7, 829.9] {
        assert_eq!(ext.eval(l).to_bits(), d65.eval_one(l).to_bits(), "{l} nm");
    }
    let at830 = d65.eval_one(830.0);
    assert!(at830 > 0.0);
    assert!((ext.eval(830.0) / at830 - 1.0).abs() < 1e-5);
    for l in [850.0f32, 900.0, 1000.0, 1600.0, 2500.0] {
        let want = at830 * planck(l, 6504.0) / planck(830.0, 6504.0);
        let got = ext.eval(l);
        assert!((got / want - 1.0).abs() < 1e-4, "{l} nm: {got} vs {want}");
    }
    assert_eq!(ext.eval(2600.0), 0.0);
}

/// A grey sky rendered to 1000 nm: the 900–1000 nm band is the tail's, not 0; its ratio to the
/// 800–900 nm band is that of the texel's spectrum (its sigmoid times the illuminant), within 3%.
/// Uniform sampling puts ~33,000 wavelength samples in each 100 nm band over the image (192
/// pixels × 256 spp × 4 lanes / 6 bands), and the map's texels vary by ~25%: each band's
/// relative standard error is ~0.6%, the ratio's ~0.8%, so 3% is ~4σ.
#[test]
fn a_grey_sky_is_lit_past_830_nm_by_the_tail() {
    let map = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/envmap_grey_16x8.exr");
    let text = format!(
        r#"(camera: (fov: 60, to_world: [LookAt(origin: (0, 0, 0), target: (0, 0, -1), up: (0, 1, 0))]),
        film: (width: 16, height: 12), sampler: (spp: 256, seed: 2),
        spectral: (range: (400, 1000), sampling: Uniform),
        emitters: [Envmap(filename: {map:?})],
        outputs: (bands: 6))"#
    );
    let job = prism::load::load_str(&text, Path::new("inline.ron")).unwrap();
    assert!(
        job.warnings
            .iter()
            .any(|w| w.contains("830 nm only") && w.contains("6504 K blackbody")),
        "{:?}",
        job.warnings
    );
    let film = prism::integrator::render(&job.scene, &job.settings, &job.channels, &|_| {}).0;
    let mean = |name: &str| {
        let c = film
            .channels
            .iter()
            .find(|c| c.name.starts_with(name))
            .unwrap_or_else(|| panic!("no {name}"));
        c.data.iter().map(|&v| v as f64).sum::<f64>() / c.data.len() as f64
    };
    let (b800, b900) = (mean("S0.850"), mean("S0.950"));
    assert!(b900 > 0.0, "the 900 nm band is black");
    // A grey texel: the sigmoid of (½, ½, ½) (rgb / 2·max) times the illuminant; the sigmoid is
    // fitted over 360–830 nm and extrapolated past it.
    let illum = prism::emitter::envmap_illuminant();
    let grey = prism::spectrum::rgb2spec::fetch([0.5; 3]);
    let band = |lo: f32| {
        (0..1000)
            .map(|k| {
                let l = lo + 0.1 * (k as f32 + 0.5);
                (grey.eval(l) * illum.eval(l)) as f64
            })
            .sum::<f64>()
    };
    let want = band(900.0) / band(800.0);
    let got = b900 / b800;
    assert!((got / want - 1.0).abs() < 0.03, "ratio {got} vs {want}");
}
