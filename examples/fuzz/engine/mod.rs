//! The mutation fuzzer's engine, shared by the long-run driver (`examples/fuzz/main.rs`) and the
//! test (`tests/fuzz.rs`). A case is a scene text, perhaps with one input file (mesh, texture,
//! spectrum table, glTF file), made by mutating the repository's own scenes and files; it is run through
//! prism (the binary, or the library in-process) and must end with exit code 0 or 2: no panic,
//! no other code, no signal, no hang past the time bound, no allocation past the memory bound.
//!
//! Scene texts carry two placeholders, so a case (and a regression case in tests/fuzz_corpus/)
//! can be replayed anywhere: `@REPO@` (the repository root) and `@CASE@` (the case's directory,
//! which holds `scene.ron` and the mutated input file).

#![allow(dead_code)]

mod damage;
mod dataset;
mod mutate;
mod oracle;
mod seeds;
mod work;

// The driver and the test each use part of the engine.
#[allow(unused_imports)]
pub use dataset::{DatasetCase, OutState};
#[allow(unused_imports)]
pub use mutate::make_case;
#[allow(unused_imports)]
pub use mutate::make_dataset_case;
#[allow(unused_imports)]
pub use oracle::{
    install_panic_hook, load_corpus_case, materialise, non_finite, present, promise, run_binary,
    run_in_process, save_finding, Limits, LIMITS, OUTPUTS,
};
#[allow(unused_imports)]
pub use oracle::{run_case_binary, run_case_in_process};
pub use seeds::load_seeds;
#[allow(unused_imports)]
pub use work::{limits_for, samples_asked};

/// What an input file is (decides the mutations and the scene that uses it).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FileKind {
    Mesh,
    Texture,
    Envmap,
    Spectrum,
    /// A glTF 2.0 scene: JSON `.gltf` (text mutations too) or the binary `.glb` container.
    Gltf,
    /// A sensor file (configs/sensors/*.ron: observers, bands, cameras, the raw model).
    Sensor,
}

/// A seed scene: its name and text with every relative path made `@REPO@/...`, the film shrunk
/// to 8×6 so that each case renders in milliseconds.
#[derive(Clone, Debug)]
pub struct SeedScene {
    pub name: String,
    pub text: String,
}

/// A seed file and a scene that reads it through `@CASE@/<name>`.
#[derive(Clone, Debug)]
pub struct SeedFile {
    pub kind: FileKind,
    /// The file name the case writes (keeps the extension, which selects the reader).
    pub name: String,
    pub bytes: Vec<u8>,
    pub host: String,
}

pub struct Seeds {
    pub scenes: Vec<SeedScene>,
    pub files: Vec<SeedFile>,
    /// Dataset configs over their base scenes (examples/fuzz/engine/dataset.rs).
    pub datasets: Vec<DatasetSeed>,
}

/// A dataset config (`scene: "scene.ron"`, beside it in the case's directory) and its base
/// scene, prepared as the scenes are (`@REPO@/...` paths, 2 frames of 8×6).
#[derive(Clone, Debug)]
pub struct DatasetSeed {
    pub name: String,
    pub config: String,
    pub scene: String,
}

/// One case: the scene text and at most one input file (name, bytes) beside it, rendered by
/// `prism render`; or, with `dataset`, a dataset config run by `prism dataset` whose base
/// scene is `scene`.
#[derive(Clone, Debug)]
pub struct Case {
    pub index: u64,
    pub what: String,
    pub scene: String,
    pub file: Option<(String, Vec<u8>)>,
    pub dataset: Option<DatasetCase>,
}

/// How a case ended.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Verdict {
    Ok(i32),
    Panic(String),
    WrongExit(i32, String),
    Signal(String),
    Hang,
    /// Exit 0 or 2 without what it promises (oracle::promise): an output left by a refusal, a
    /// refusal naming no file, a render with a non-finite pixel.
    Broken(String),
}

impl Verdict {
    pub fn is_ok(&self) -> bool {
        matches!(self, Verdict::Ok(_))
    }
    pub fn label(&self) -> &'static str {
        match self {
            Verdict::Ok(_) => "ok",
            Verdict::Panic(_) => "panic",
            Verdict::WrongExit(..) => "wrong-exit",
            Verdict::Signal(_) => "signal",
            Verdict::Hang => "hang",
            Verdict::Broken(_) => "broken",
        }
    }
}
