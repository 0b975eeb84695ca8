//! The render pipeline: what every subcommand that renders shares.

pub mod workers;

pub use workers::{worker_pool, WorkerArgs};
