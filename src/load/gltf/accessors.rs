//! Accessor extents, checked before any data is read: the crate trusts `count` (an index count
//! of 2^62 would be allocated or read past its buffer) and sparse indices (one past the
//! accessor's count was silently dropped). Each accessor's elements, and its sparse indices
//! and values, must fit their buffer views, each view its buffer (glTF 2.0 §3.6.2, §5.1), and
//! each sparse index must be below the accessor's count and above the one before (§5.1.7).

use super::err;
use crate::error::InputError;
use serde_json::Value;
use std::path::Path;

/// The most elements an accessor without a buffer view (zeros, perhaps with sparse values)
/// may have: 2^28, past any mesh prism can hold in memory (4 GB of VEC3 floats), far below
/// the counts that would overflow an allocation.
pub const MAX_UNBACKED_COUNT: u64 = 1 << 28;

const HINT: &str = "re-export the model (the file's accessors do not match its buffers), or check it with the Khronos glTF validator";

/// The byte size of one component of `component_type` (glTF 2.0 §3.6.2.2).
fn component_size(component_type: Option<u64>) -> u64 {
    match component_type {
        Some(5120 | 5121) => 1,
        Some(5122 | 5123) => 2,
        _ => 4,
    }
}

/// The byte size of one element of accessor `a` (also the least byteStride, `checks.rs`).
pub(super) fn element_size(a: &Value) -> u64 {
    let n = match a.get("type").and_then(Value::as_str) {
        Some("SCALAR") => 1,
        Some("VEC2") => 2,
        Some("VEC3") => 3,
        Some("VEC4" | "MAT2") => 4,
        Some("MAT3") => 9,
        _ => 16,
    };
    n * component_size(a.get("componentType").and_then(Value::as_u64))
}

fn num(v: &Value, key: &str) -> u64 {
    v.get(key).and_then(Value::as_u64).unwrap_or(0)
}

/// The byte length of buffer view `k`, once checked to fit its buffer; None if there is no such
/// view (the crate's validator reports a bad index).
fn view_length(path: &Path, json: &Value, k: u64) -> Result<Option<(u64, u64)>, InputError> {
    let Some(view) = json.pointer(&format!("/bufferViews/{k}")) else {
        return Ok(None);
    };
    let (offset, length) = (num(view, "byteOffset"), num(view, "byteLength"));
    let buffer = view
        .get("buffer")
        .and_then(Value::as_u64)
        .and_then(|b| json.pointer(&format!("/buffers/{b}")));
    if let Some(b) = buffer {
        let size = num(b, "byteLength");
        if offset as u128 + length as u128 > size as u128 {
            return Err(err(
                path,
                format!("bufferViews[{k}]"),
                format!(
                    "the view's bytes {offset}..{} run past its buffer's {size}",
                    offset as u128 + length as u128
                ),
            )
            .hint(HINT));
        }
    }
    let stride = view.get("byteStride").and_then(Value::as_u64);
    Ok(Some((length, stride.unwrap_or(0))))
}

/// Checks that `count` elements of `size` bytes from `offset` fit buffer view `view`
/// (`stride` 0: packed).
#[allow(clippy::too_many_arguments)]
fn fits(
    path: &Path,
    json: &Value,
    field: &str,
    view: u64,
    offset: u64,
    count: u64,
    size: u64,
    what: &str,
) -> Result<(), InputError> {
    let Some((length, stride)) = view_length(path, json, view)? else {
        return Ok(());
    };
    let stride = if stride == 0 { size } else { stride };
    // u128: count and stride are the file's, up to 2^64 each.
    let end = offset as u128 + stride as u128 * (count.max(1) - 1) as u128 + size as u128;
    if end > length as u128 {
        return Err(err(
            path,
            field,
            format!(
                "{count} {what} of {size} bytes need {end} bytes of bufferViews[{view}], which has {length}"
            ),
        )
        .hint(HINT));
    }
    Ok(())
}

/// Checks every accessor's count and extent (and its sparse part's) on the JSON.
pub fn check_extents(path: &Path, json: &Value) -> Result<(), InputError> {
    let accessors = json.get("accessors").and_then(Value::as_array);
    for (i, a) in accessors.into_iter().flatten().enumerate() {
        let at = format!("accessors[{i}]");
        let count = num(a, "count");
        let size = element_size(a);
        if count == 0 {
            return Err(
                err(path, format!("{at}.count"), "an accessor needs a count ≥ 1").hint(HINT),
            );
        }
        match a.get("bufferView").and_then(Value::as_u64) {
            Some(v) => fits(path, json, &format!("{at}.count"), v, num(a, "byteOffset"), count, size, "elements")?,
            None if count > MAX_UNBACKED_COUNT => {
                return Err(err(
                    path,
                    format!("{at}.count"),
                    format!("a count of {count} without a buffer view is beyond {MAX_UNBACKED_COUNT}, more elements than prism can hold"),
                )
                .hint(HINT))
            }
            None => {}
        }
        let Some(s) = a.get("sparse") else { continue };
        let at = format!("{at}.sparse");
        let n = num(s, "count");
        if n == 0 || n > count {
            return Err(err(
                path,
                format!("{at}.count"),
                format!("a sparse count of {n} is not in [1, {count}] (the accessor's count)"),
            )
            .hint(HINT));
        }
        for (part, size) in [
            (
                "indices",
                component_size(s.pointer("/indices/componentType").and_then(Value::as_u64)),
            ),
            ("values", size),
        ] {
            let Some(p) = s.get(part) else { continue };
            if let Some(v) = p.get("bufferView").and_then(Value::as_u64) {
                fits(
                    path,
                    json,
                    &format!("{at}.{part}"),
                    v,
                    num(p, "byteOffset"),
                    n,
                    size,
                    part,
                )?;
            }
        }
    }
    Ok(())
}

/// Checks each sparse index (in the loaded buffers) is below its accessor's count and
/// increasing: the crate silently drops an index past the count.
pub fn check_sparse(
    path: &Path,
    doc: &gltf::Document,
    buffers: &[gltf::buffer::Data],
) -> Result<(), InputError> {
    use gltf::accessor::sparse::IndexType;
    for a in doc.accessors() {
        let Some(s) = a.sparse() else { continue };
        let ix = s.indices();
        let view = ix.view();
        let Some(data) = buffers.get(view.buffer().index()) else {
            continue;
        };
        let size = match ix.index_type() {
            IndexType::U8 => 1,
            IndexType::U16 => 2,
            IndexType::U32 => 4,
        };
        let start = view.offset() + ix.offset();
        let Some(bytes) = data.0.get(start..start + size * s.count()) else {
            continue; // `check_extents` and the buffer's length check refuse this first.
        };
        let mut last: Option<u64> = None;
        for (k, c) in bytes.chunks_exact(size).enumerate() {
            let v = c.iter().rev().fold(0u64, |acc, &b| acc << 8 | b as u64);
            let problem = if v >= a.count() as u64 {
                format!(
                    "sparse index {k} is {v}, past the accessor's {} elements",
                    a.count()
                )
            } else if last.is_some_and(|l| v <= l) {
                format!(
                    "sparse index {k} is {v}, not above the one before ({})",
                    last.unwrap_or(0)
                )
            } else {
                last = Some(v);
                continue;
            };
            return Err(err(path, format!("accessors[{}].sparse.indices", a.index()), problem)
                .hint("sparse indices must increase and stay below the accessor's count (glTF 2.0 §5.1.7); re-export the model"));
        }
    }
    Ok(())
}
