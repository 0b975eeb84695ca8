//! `prism dataset`: many frames from one base scene, each with its own draws of named scene
//! elements (camera, lights, materials, objects), reproducible frame by frame from (dataset
//! seed, frame index) alone, resumable and shardable. The dataset layer edits the base scene's
//! config for each frame and renders it through `frame::render_frame`, so every channel a scene
//! can ask for comes along. configs/README.md documents the config and the output folder.

pub mod animation;
pub mod apply;
pub mod asset_folder;
pub mod assets;
pub mod base;
pub mod check_frames;
pub mod cli;
pub mod config;
pub mod digits;
pub mod export;
pub mod files;
pub mod frame;
pub mod illuminant_files;
pub mod intrinsics;
pub mod library;
pub mod manifest;
pub mod place;
pub mod plan;
pub mod run;
pub mod sequence;
pub mod sheet;
pub mod sheet_layers;
pub mod textures;
pub mod vary;
pub mod view;

pub use base::Base;
pub use config::DatasetConfig;
pub use plan::{plan, FramePlan};
