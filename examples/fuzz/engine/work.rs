//! The CPU bound of a case, from the work it asks for: a render of many samples is long, not
//! stuck. Run 13 (seed 20261205) flagged case 731603 as a hang at the flat 20 s bound: a
//! dataset case of 2 frames of 80×6 at 32,768 spp (31.5 M samples), which alone exits 0 after
//! 30.6 s of CPU. A busy loop is still caught, later in proportion to the work asked for.

use super::{Case, Limits};

/// CPU seconds allowed per camera sample asked for: 5 µs, five times what case 731603 took
/// (0.97 µs), for deeper paths and the checks around the render.
const SECONDS_PER_SAMPLE: f64 = 5e-6;

/// The largest CPU bound any case gets (10 minutes).
const MAX_CPU_SECONDS: u64 = 600;

/// `limits` with the CPU bound raised for the samples `case` asks for.
pub fn limits_for(case: &Case, limits: &Limits) -> Limits {
    // Whole seconds (a small case keeps its bound).
    let extra = (samples_asked(case) * SECONDS_PER_SAMPLE).round();
    let cpu = (limits.cpu_seconds as f64 + extra).min(MAX_CPU_SECONDS as f64);
    Limits {
        cpu_seconds: (cpu as u64).max(limits.cpu_seconds),
        ..*limits
    }
}

/// The camera samples a case can ask for, over-estimated from its text: the largest film width
/// and height and `spp` written anywhere, multiplied. A render case runs at `--spp 1`, a
/// dataset case at `--frames 0..2` (oracle.rs, dataset.rs).
pub fn samples_asked(case: &Case) -> f64 {
    match &case.dataset {
        None => film(&[&case.scene]),
        Some(d) => {
            let texts = [d.config.as_str(), case.scene.as_str()];
            2.0 * largest(&texts, "spp").max(1.0) * film(&texts)
        }
    }
}

/// Width × height: `width:`/`height:` fields or a `resolution: (W, H)`.
fn film(texts: &[&str]) -> f64 {
    let w = largest(texts, "width").max(largest(texts, "resolution"));
    let h = largest(texts, "height").max(largest_second(texts, "resolution"));
    w.max(1.0) * h.max(1.0)
}

/// The largest number written right after `key:` (after an opening `(` or `Fixed(`), 0 if none.
fn largest(texts: &[&str], key: &str) -> f64 {
    values(texts, key).map(|(a, _)| a).fold(0.0, f64::max)
}

/// The largest second number of a `key: (a, b)` pair.
fn largest_second(texts: &[&str], key: &str) -> f64 {
    values(texts, key)
        .filter_map(|(_, b)| b)
        .fold(0.0, f64::max)
}

/// Each `key:` value in `texts` as (first number, second number of a pair).
fn values<'a>(texts: &'a [&'a str], key: &'a str) -> impl Iterator<Item = (f64, Option<f64>)> + 'a {
    let pat = format!("{key}:");
    texts.iter().flat_map(move |t| {
        let pat = pat.clone();
        t.match_indices(&pat)
            .filter(|(i, _)| {
                // A whole field name (`max_spp:` is not `spp:`).
                !t[..*i]
                    .chars()
                    .next_back()
                    .is_some_and(|c| c.is_alphanumeric() || c == '_')
            })
            .map(|(i, _)| {
                let rest = t[i + pat.len()..].trim_start();
                let rest = rest.strip_prefix("Fixed(").unwrap_or(rest);
                let rest = rest.strip_prefix('(').unwrap_or(rest).trim_start();
                let (a, tail) = number(rest);
                let b = tail
                    .trim_start()
                    .strip_prefix(',')
                    .map(|r| number(r.trim_start()).0);
                (a, b)
            })
            .collect::<Vec<_>>()
    })
}

/// The number at the start of `s` (0 if none) and what follows it.
fn number(s: &str) -> (f64, &str) {
    let end = s
        .find(|c: char| !(c.is_ascii_digit() || matches!(c, '.' | 'e' | 'E' | '+' | '-')))
        .unwrap_or(s.len());
    let v = s[..end].parse::<f64>().ok().filter(|v| v.is_finite());
    (v.unwrap_or(0.0).abs(), &s[end..])
}
