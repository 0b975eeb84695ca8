//! What changed between the `dataset.json` a folder holds and the dataset of a run, named for
//! the user (`manifest/claim.rs` refuses a folder of another dataset with this list).

use serde_json::Value;

/// The paths where `a` and `b` differ, as `path: old → new`.
pub(super) fn diff(a: &Value, b: &Value, path: &str, out: &mut Vec<String>) {
    match (a, b) {
        // The input files' hashes: name the file, not its hash.
        (Value::Object(x), Value::Object(y)) if path == "inputs" => {
            let keys: std::collections::BTreeSet<&String> = x.keys().chain(y.keys()).collect();
            for k in keys {
                match (x.get(k), y.get(k)) {
                    (Some(u), Some(v)) if u != v => {
                        out.push(format!("the contents of the input file `{k}`"))
                    }
                    (None, Some(_)) => out.push(format!("a new input file `{k}`")),
                    (Some(_), None) => out.push(format!("the input file `{k}` is no longer read")),
                    _ => {}
                }
            }
        }
        (Value::Object(x), Value::Object(y)) => {
            let keys: std::collections::BTreeSet<&String> = x.keys().chain(y.keys()).collect();
            for k in keys {
                if k == "hash" {
                    continue;
                }
                let p = if path.is_empty() {
                    k.clone()
                } else {
                    format!("{path}.{k}")
                };
                diff(
                    x.get(k).unwrap_or(&Value::Null),
                    y.get(k).unwrap_or(&Value::Null),
                    &p,
                    out,
                );
            }
        }
        (Value::Array(x), Value::Array(y)) if x.len() == y.len() => {
            for (i, (u, v)) in x.iter().zip(y).enumerate() {
                diff(u, v, &format!("{path}[{i}]"), out);
            }
        }
        // The same f32 read back (configs are f32, JSON holds the f64 it widens to): no change.
        (Value::Number(x), Value::Number(y))
            if x.as_f64()
                .zip(y.as_f64())
                .is_some_and(|(u, v)| u as f32 == v as f32) => {}
        _ if a != b => {
            let short = |v: &Value| {
                // A config's f32 as written (0.3), not as JSON's f64 holds it (0.30000001…).
                let s = match v.as_f64() {
                    Some(x) if v.is_f64() && (x as f32) as f64 == x => (x as f32).to_string(),
                    _ => v.to_string(),
                };
                if s.chars().count() > 40 {
                    format!("{}…", s.chars().take(40).collect::<String>())
                } else {
                    s
                }
            };
            out.push(format!("{path}: {} → {}", short(a), short(b)));
        }
        _ => {}
    }
}
