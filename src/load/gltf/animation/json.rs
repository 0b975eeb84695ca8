//! The raw JSON of a file's animations checked before the gltf crate reads them (`super`).

use super::{err, REEXPORT};
use crate::error::InputError;
use serde_json::Value;
use std::path::Path;

/// Checks every animation's samplers and channels in the raw JSON: indices in range, input
/// accessors SCALAR floats, outputs of the channel's type (VEC3, VEC4 rotations of floats or
/// normalised integers), and as many outputs as inputs (three times as many, CUBICSPLINE).
pub fn check_json(path: &Path, json: &Value) -> Result<(), InputError> {
    let list = |k: &str| json.get(k).and_then(Value::as_array).cloned();
    let accessors = list("accessors").unwrap_or_default();
    let nodes = list("nodes").map_or(0, |n| n.len());
    for (a, anim) in list("animations").unwrap_or_default().iter().enumerate() {
        let at = format!("animations[{a}]");
        let samplers = anim
            .get("samplers")
            .and_then(Value::as_array)
            .cloned()
            .unwrap_or_default();
        let channels = anim.get("channels").and_then(Value::as_array);
        for (c, ch) in channels.into_iter().flatten().enumerate() {
            let cf = format!("{at}.channels[{c}]");
            let target = ch.get("target");
            let prop = target
                .and_then(|t| t.get("path"))
                .and_then(Value::as_str)
                .unwrap_or("");
            if let Some(n) = target.and_then(|t| t.get("node")) {
                if n.as_u64().is_none_or(|k| k as usize >= nodes) {
                    return Err(err(
                        path,
                        format!("{cf}.target.node"),
                        format!("node {n} does not exist (the file has {nodes})"),
                        REEXPORT,
                    ));
                }
            }
            let s = ch.get("sampler").and_then(Value::as_u64);
            let Some(sampler) = s.and_then(|k| samplers.get(k as usize)) else {
                return Err(err(
                    path,
                    format!("{cf}.sampler"),
                    format!(
                        "sampler {} does not exist (the animation has {})",
                        s.map_or("(none)".into(), |s| s.to_string()),
                        samplers.len()
                    ),
                    REEXPORT,
                ));
            };
            let sf = format!("{at}.samplers[{}]", s.unwrap_or(0));
            let input = accessor(
                path,
                &accessors,
                sampler.get("input"),
                format!("{sf}.input"),
            )?;
            let output = accessor(
                path,
                &accessors,
                sampler.get("output"),
                format!("{sf}.output"),
            )?;
            let ty = |a: &Value| {
                a.get("type")
                    .and_then(Value::as_str)
                    .unwrap_or("")
                    .to_owned()
            };
            let comp = |a: &Value| a.get("componentType").and_then(Value::as_u64).unwrap_or(0);
            let count = |a: &Value| a.get("count").and_then(Value::as_u64).unwrap_or(0);
            if ty(input) != "SCALAR" || comp(input) != 5126 {
                return Err(err(
                    path,
                    format!("{sf}.input"),
                    format!(
                        "a sampler's input (its key times) must be a SCALAR float accessor, not {} of component type {}",
                        ty(input),
                        comp(input)
                    ),
                    REEXPORT,
                ));
            }
            let (want, comps): (&str, &[u64]) = match prop {
                "translation" | "scale" => ("VEC3", &[5126]),
                "rotation" => ("VEC4", &[5126, 5120, 5121, 5122, 5123]),
                "weights" => ("SCALAR", &[5126, 5120, 5121, 5122, 5123]),
                // The crate marks any other value invalid and panics when its channel is read
                // (fuzz run 12, case 70507: "rota\u{feff}tion"), so it is refused here.
                _ => {
                    return Err(err(
                        path,
                        format!("{cf}.target.path"),
                        format!("the target path {prop:?} is not one of translation, rotation, scale, weights"),
                        REEXPORT,
                    ))
                }
            };
            // The same for the sampler's interpolation (LINEAR when absent).
            match sampler.get("interpolation") {
                None => {}
                Some(Value::String(i))
                    if matches!(i.as_str(), "LINEAR" | "STEP" | "CUBICSPLINE") => {}
                Some(i) => {
                    return Err(err(
                        path,
                        format!("{sf}.interpolation"),
                        format!("the interpolation {i} is not one of LINEAR, STEP, CUBICSPLINE"),
                        REEXPORT,
                    ))
                }
            }
            if ty(output) != want || !comps.contains(&comp(output)) {
                return Err(err(
                    path,
                    format!("{sf}.output"),
                    format!(
                        "a {prop} channel's output must be a {want} accessor of {}, not {} of component type {}",
                        if comps.len() > 1 { "floats or normalised integers" } else { "floats" },
                        ty(output),
                        comp(output)
                    ),
                    REEXPORT,
                ));
            }
            if prop == "weights" {
                continue; // not read: any multiple of the targets' count
            }
            let per = match sampler.get("interpolation").and_then(Value::as_str) {
                Some("CUBICSPLINE") => 3,
                _ => 1,
            };
            if count(input) == 0 || count(output) != per * count(input) {
                return Err(err(
                    path,
                    format!("{sf}.output"),
                    format!(
                        "the sampler has {} key times but {} outputs; a {} sampler needs {}",
                        count(input),
                        count(output),
                        if per == 3 {
                            "CUBICSPLINE"
                        } else {
                            "LINEAR or STEP"
                        },
                        if per == 3 {
                            "three per key (in-tangent, value, out-tangent)"
                        } else {
                            "one per key"
                        }
                    ),
                    REEXPORT,
                ));
            }
        }
    }
    Ok(())
}

/// Accessor `v` (an index) of `accessors`, or an error naming `field`.
fn accessor<'a>(
    path: &Path,
    accessors: &'a [Value],
    v: Option<&Value>,
    field: String,
) -> Result<&'a Value, InputError> {
    v.and_then(Value::as_u64)
        .and_then(|k| accessors.get(k as usize))
        .ok_or_else(|| {
            err(
                path,
                field,
                format!(
                    "the accessor {} does not exist (the file has {})",
                    v.map_or("(none)".into(), |v| v.to_string()),
                    accessors.len()
                ),
                REEXPORT,
            )
        })
}
