//! Every scene under scenes/ on a small film, and a render's bits: shared by the tests that
//! compare renders bit for bit (tests/packet.rs, tests/portable_bits.rs).

use prism::integrator::packet::Simd;
use prism::load::Job;
use std::path::{Path, PathBuf};

/// Every scene file under scenes/, sorted.
pub fn scenes() -> Vec<PathBuf> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        for e in std::fs::read_dir(dir).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                walk(&p, out);
            } else if p.extension().is_some_and(|x| x == "ron") {
                out.push(p);
            }
        }
    }
    let mut out = Vec::new();
    walk(Path::new("scenes"), &mut out);
    out.sort();
    out
}

/// `scene` on a small film (20×15, the camera's own aspect kept where its intrinsics fix the
/// film size) at 3 spp: 3 is not a multiple of any width, so packets straddle pixels.
pub fn job(scene: &Path, simd: Simd) -> Result<Job, String> {
    let small = prism::load::load(scene, |cfg| {
        cfg.film.width = 20;
        cfg.film.height = 15;
        cfg.sampler.spp = prism::config::Spp::Fixed(3);
    });
    let mut job = match small {
        Ok(j) => j,
        // Intrinsics given in pixels tie the camera to its film: keep the scene's size, 1 spp.
        Err(_) => prism::load::load(scene, |cfg| cfg.sampler.spp = prism::config::Spp::Fixed(1))
            .map_err(|e| e.to_string())?,
    };
    job.settings.simd = simd;
    Ok(job)
}

/// Every channel's bits (float channels, then the uint ones), rendered on `threads` threads.
pub fn render(job: &Job, threads: usize) -> Vec<(String, Vec<u32>)> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    let r = pool.install(|| prism::pipeline::render(job, 1.0, &|_| {}));
    let mut out: Vec<(String, Vec<u32>)> = r
        .film
        .channels
        .iter()
        .map(|c| (c.name.clone(), c.data.iter().map(|v| v.to_bits()).collect()))
        .collect();
    out.extend(
        r.film
            .uint_channels
            .iter()
            .map(|c| (c.name.clone(), c.data.clone())),
    );
    out
}

/// The first channel and pixel where two renders differ.
pub fn first_difference(a: &[(String, Vec<u32>)], b: &[(String, Vec<u32>)]) -> Option<String> {
    if a.len() != b.len() {
        return Some(format!("{} channels against {}", a.len(), b.len()));
    }
    for ((name, x), (_, y)) in a.iter().zip(b) {
        if let Some(i) = x.iter().zip(y).position(|(p, q)| p != q) {
            return Some(format!(
                "channel {name}, value {i}: {} against {}",
                f32::from_bits(x[i]),
                f32::from_bits(y[i])
            ));
        }
    }
    None
}
