//! Build-time work: embed the spectral data files of `spectra/` into the binary (so `prism` runs
//! from anywhere) and fit the RGB-to-spectrum coefficient table from those data.

use std::env;
use std::fmt::Write as _;
use std::fs;
use std::path::{Path, PathBuf};

fn main() {
    let root = PathBuf::from(env::var("CARGO_MANIFEST_DIR").unwrap());
    let out = PathBuf::from(env::var("OUT_DIR").unwrap());
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=spectra");
    host_cpu_cfgs();
    warn_fused_builds();
    embed_spectra(&root.join("spectra"), &out.join("spectra_files.rs"));
    fit_rgb_table(&root, &out);
}

/// `prism_host_avx2` / `prism_host_sse41` when the building CPU has them and builds for itself:
/// the tests of the SIMD paths are then run, and otherwise reported as ignored with the reason
/// (a runtime check inside a test could only pass silently).
fn host_cpu_cfgs() {
    println!("cargo:rustc-check-cfg=cfg(prism_host_avx2)");
    println!("cargo:rustc-check-cfg=cfg(prism_host_sse41)");
    #[cfg(target_arch = "x86_64")]
    if env::var("CARGO_CFG_TARGET_ARCH").as_deref() == Ok("x86_64") {
        if std::is_x86_feature_detected!("avx2") {
            println!("cargo:rustc-cfg=prism_host_avx2");
        }
        if std::is_x86_feature_detected!("sse4.1") && std::is_x86_feature_detected!("ssse3") {
            println!("cargo:rustc-cfg=prism_host_sse41");
        }
    }
}

/// A build with FMA enabled at compile time (`-C target-cpu=native` on most x86 CPUs of the
/// last decade, `x86-64-v3`) renders other low bits: glam's SIMD matrix products fuse the
/// multiply and the add there (measured: every channel of the Cornell box differs;
/// docs/performance.md). The same bits on every node of a cluster hold for the default build,
/// which chooses its AVX2 code at run time, so an FMA build says so where it is made.
fn warn_fused_builds() {
    let features = env::var("CARGO_CFG_TARGET_FEATURE").unwrap_or_default();
    if env::var("CARGO_CFG_TARGET_ARCH").as_deref() == Ok("x86_64")
        && features.split(',').any(|f| f == "fma")
    {
        println!(
            "cargo:warning=prism built with FMA enabled (e.g. -C target-cpu=native): its renders \
             differ in their lowest bits from the default build's; build without it for frames \
             that match other machines bit for bit"
        );
    }
}

// `rgb2spec_fit.rs` refers to its sibling as `super::table`, as in the crate; mirroring
// `crate::spectrum` here makes that path resolve. Only part of their API is used by the build.
#[allow(dead_code, unused_imports)]
#[path = "src/spectrum"]
mod spectrum {
    pub mod gamut;
    pub mod rgb2spec_fit;
    pub mod table;
}

// The fit's maths is the crate's own (`crate::math::portable`), so a build on any host gives the
// same tables.
#[allow(dead_code)]
#[path = "src/math"]
mod math {
    pub mod portable;
}

/// Fits the sigmoid coefficient tables (Jakob & Hanika 2019) of every input RGB space (linear
/// sRGB, Rec. 2020, Display P3, ACEScg; `src/spectrum/gamut.rs`) from the CIE data in
/// `spectra/` and writes them to `<space>_sigmoid.bin`, which `src/spectrum/rgb2spec.rs` embeds.
/// Each fit's time goes to the build script's output (`target/*/build/prism-*/output`) and to
/// `fit_times.txt` beside the tables.
fn fit_rgb_table(root: &Path, out: &Path) {
    use spectrum::gamut::ALL_GAMUTS;
    use spectrum::rgb2spec_fit::{fit_table, FitData};
    // The sources of the fit (`rgb2spec_fit.rs` and what it includes).
    let fit_sources = [
        "src/spectrum/rgb2spec_fit.rs",
        "src/spectrum/rgb2spec_fit/coeffs.rs",
        "src/spectrum/table.rs",
        "src/spectrum/gamut.rs",
    ];
    for src in fit_sources {
        println!("cargo:rerun-if-changed={}", root.join(src).display());
    }
    let read = |rel: &str| {
        let path = root.join("spectra").join(rel);
        fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
    };
    let (cmf, d65) = (read("cmf/CIE1931_2deg.txt"), read("illuminants/D65.txt"));
    let data =
        FitData::from_texts(&cmf, &d65).unwrap_or_else(|e| panic!("RGB uplifting data: {e}"));
    // The fit depends only on these inputs: a table whose key (a hash of them) matches the one
    // stored beside it from an earlier run is kept, so editing another file of `spectra/`
    // (which re-runs this script) does not refit.
    let sources: Vec<String> = fit_sources
        .iter()
        .map(|p| fs::read_to_string(root.join(p)).unwrap())
        .collect();
    let mut times = String::new();
    for gamut in ALL_GAMUTS {
        let res = 64;
        let mut key = Fnv::new();
        for text in sources.iter().chain([&cmf, &d65]) {
            key.add(text.as_bytes());
        }
        key.add(gamut.name().as_bytes());
        key.add(&(res as u64).to_le_bytes());
        let key = format!("{:016x}", key.0);
        let (file, key_file) = (
            out.join(gamut.table_file()),
            out.join(format!("{}.key", gamut.table_file())),
        );
        let line = if file.exists()
            && fs::read_to_string(&key_file).ok().as_deref() == Some(key.as_str())
        {
            format!(
                "{}: {res}³ table unchanged (key {key}), not refitted",
                gamut.name()
            )
        } else {
            let start = std::time::Instant::now();
            let table = fit_table(&data.clone().with_matrix(gamut.to_xyz()), res);
            fs::write(&file, table.to_bytes()).unwrap();
            fs::write(&key_file, &key).unwrap();
            format!(
                "{}: {res}³ table fitted in {:.2} s",
                gamut.name(),
                start.elapsed().as_secs_f64()
            )
        };
        println!("{line}");
        times.push_str(&line);
        times.push('\n');
    }
    fs::write(out.join("fit_times.txt"), times).unwrap();
}

/// Writes `spectra_files.rs`: `pub static FILES: &[(&str, &str)]`, each entry a path relative to
/// `spectra/` without its `.txt` extension (e.g. `illuminants/D65`) and the file's text.
fn embed_spectra(dir: &Path, out: &Path) {
    let mut files = Vec::new();
    collect_txt(dir, dir, &mut files);
    files.sort();
    let mut code = String::from("pub static FILES: &[(&str, &str)] = &[\n");
    for (key, path) in &files {
        println!("cargo:rerun-if-changed={}", path.display());
        writeln!(
            code,
            "    ({key:?}, include_str!({:?})),",
            path.display().to_string()
        )
        .unwrap();
    }
    code.push_str("];\n");
    fs::write(out, code).unwrap();
}

fn collect_txt(root: &Path, dir: &Path, files: &mut Vec<(String, PathBuf)>) {
    let mut entries: Vec<_> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            println!("cargo:rerun-if-changed={}", path.display());
            collect_txt(root, &path, files);
        } else if path.extension().is_some_and(|e| e == "txt") {
            let rel = path.strip_prefix(root).unwrap().with_extension("");
            let key = rel.to_string_lossy().replace('\\', "/");
            files.push((key, path));
        }
    }
}

/// FNV-1a, 64 bit: a hash that is the same on every run and toolchain (for the table cache).
struct Fnv(u64);

impl Fnv {
    fn new() -> Fnv {
        Fnv(0xcbf2_9ce4_8422_2325)
    }

    fn add(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0 ^ b as u64).wrapping_mul(0x0100_0000_01b3);
        }
        // A separator, so ("ab", "c") and ("a", "bc") differ.
        self.0 = (self.0 ^ 0xff).wrapping_mul(0x0100_0000_01b3);
    }
}
