//! The one door for input files: every file a scene names is opened here (size limits, regular
//! files only) and recorded (`inputs`: what a render read, so no output may overwrite it).
//! A leaf of the base floor: it knows no engine or config type.

pub mod input_file;
pub mod inputs;
pub mod paths;
