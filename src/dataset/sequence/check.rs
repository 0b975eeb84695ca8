//! The sequence fields' own checks (`dataset::config` calls them while it reads the config).

use super::Trajectory;
use crate::error::InputError;

/// The sequence fields' own checks; sets `frames` to sequences × frames_per_sequence.
pub fn check(
    c: &mut crate::dataset::DatasetConfig,
    file: &std::path::Path,
) -> Result<(), InputError> {
    let err = |field: &str, message: String, hint: &str| {
        Err(InputError::new(file, message).field(field).hint(hint))
    };
    if c.sequences == 0 {
        if c.frames_per_sequence != 0 || c.fps != 0.0 || c.motion.is_some() {
            return err(
                "sequences",
                "frames_per_sequence, fps and motion describe video sequences, and sequences is not given".into(),
                "give sequences: N (how many), or drop frames_per_sequence, fps and motion",
            );
        }
        return Ok(());
    }
    if c.frames_per_sequence == 0 {
        return err(
            "frames_per_sequence",
            "sequences need frames_per_sequence ≥ 1".into(),
            "e.g. frames_per_sequence: 8",
        );
    }
    if !(c.fps.is_finite() && c.fps > 0.0 && c.fps <= 1e6) {
        return err(
            "fps",
            format!(
                "fps {} must be a positive number of frames per second",
                c.fps
            ),
            "e.g. fps: 24",
        );
    }
    let total = c.sequences as u64 * c.frames_per_sequence as u64;
    if total > crate::dataset::config::MAX_FRAMES as u64 {
        return err(
            "sequences",
            format!(
                "{} sequences of {} frames make {total} frames, more than {}",
                c.sequences,
                c.frames_per_sequence,
                crate::dataset::config::MAX_FRAMES
            ),
            "split a larger dataset into several configs with different seeds",
        );
    }
    if c.frames != 0 && c.frames as u64 != total {
        return err(
            "frames",
            format!(
                "frames: {} differs from sequences × frames_per_sequence = {total}",
                c.frames
            ),
            "leave frames out with sequences (it is their product)",
        );
    }
    c.frames = total as u32;
    let m = c.motion.clone().unwrap_or_default();
    if !(m.shutter.is_finite() && (0.0..=1.0).contains(&m.shutter)) {
        return err(
            "motion.shutter",
            format!(
                "shutter {} must be a fraction of the frame interval in [0, 1]",
                m.shutter
            ),
            "e.g. shutter: 0.5 (a 180° shutter), 0 for instants",
        );
    }
    let ranges = m
        .objects
        .iter()
        .enumerate()
        .flat_map(|(k, o)| {
            [
                (format!("motion.objects[{k}].speed"), o.speed),
                (format!("motion.objects[{k}].spin"), o.spin),
            ]
        })
        .chain(m.lights.iter().enumerate().flat_map(|(k, l)| {
            [
                (format!("motion.lights[{k}].speed"), l.speed),
                (format!("motion.lights[{k}].orbit"), l.orbit),
            ]
        }))
        .chain(match &m.camera {
            Some(
                Trajectory::Orbit { speed }
                | Trajectory::Dolly { speed }
                | Trajectory::Walk { speed, .. },
            ) => Some(("motion.camera.speed".to_string(), *speed)),
            _ => None,
        });
    for (field, (lo, hi)) in ranges {
        if !(lo.is_finite() && hi.is_finite() && lo <= hi) {
            return err(
                &field,
                format!("the range ({lo}, {hi}) must be finite and increasing"),
                "give (lo, hi) with lo ≤ hi",
            );
        }
    }
    if let Some(Trajectory::Walk { turn, .. }) = &m.camera {
        if !(turn.is_finite() && *turn >= 0.0) {
            return err(
                "motion.camera.turn",
                format!("turn {turn} must be ≥ 0 degrees per second"),
                "e.g. turn: 30",
            );
        }
    }
    if let Some(Trajectory::Keyframes(keys)) = &m.camera {
        if keys.is_empty() {
            return err(
                "motion.camera",
                "Keyframes needs at least one key".into(),
                "e.g. Keyframes([(time: 0, origin: (0, 1, 4), target: (0, 0, 0))])",
            );
        }
    }
    Ok(())
}
