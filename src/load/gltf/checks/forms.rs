//! The forms a glTF file's accessors and images must have before the crate reads them: each
//! primitive's index and attribute accessors of an allowed component type and type, each
//! accessor's element within its buffer view's stride, each image with a source. The crate
//! reaches `unreachable!`, an assertion or an `unwrap` on any other (fuzzer findings).

use crate::error::InputError;
use crate::load::gltf::accessors::element_size;
use crate::load::gltf::err;
use serde_json::Value;
use std::path::Path;

/// The component types (glTF 2.0 §3.7.2.1) each attribute may have, with its types; the
/// crate's readers reach `unreachable!` on any other (the fuzzer found indices of type 3).
fn attribute_forms(name: &str) -> Option<(&'static [u64], &'static [&'static str])> {
    const F32: &[u64] = &[5126];
    const UV: &[u64] = &[5126, 5121, 5123];
    Some(match name {
        "POSITION" | "NORMAL" => (F32, &["VEC3"]),
        "TANGENT" => (F32, &["VEC4"]),
        n if n.starts_with("TEXCOORD_") => (UV, &["VEC2"]),
        n if n.starts_with("COLOR_") => (UV, &["VEC3", "VEC4"]),
        _ => return None,
    })
}

/// Each primitive's index and attribute accessors have the component type and type the
/// specification allows; each image has a `uri` or a `bufferView` with a `mimeType` (the
/// crate unwraps both).
pub(super) fn check_forms(path: &Path, json: &Value) -> Result<(), InputError> {
    let accessors = json.get("accessors").and_then(Value::as_array);
    let form = |k: &Value| {
        let a = accessors.and_then(|a| a.get(k.as_u64()? as usize))?;
        Some((
            a.get("componentType")?.as_u64()?,
            a.get("type")?.as_str()?.to_owned(),
        ))
    };
    let bad = |field: String, what: &str, got: Option<(u64, String)>| {
        let got = got.map_or("no accessor".into(), |(c, t)| {
            format!("componentType {c}, type {t}")
        });
        err(path, field, format!("the accessor has {got}; glTF 2.0 wants {what}"))
            .hint("re-export the model (the file breaks the specification's accessor rules), or check it with the Khronos glTF validator")
    };
    let meshes = json.get("meshes").and_then(Value::as_array);
    for (i, m) in meshes.into_iter().flatten().enumerate() {
        let prims = m.get("primitives").and_then(Value::as_array);
        for (j, p) in prims.into_iter().flatten().enumerate() {
            let at = format!("meshes[{i}].primitives[{j}]");
            if let Some(k) = p.get("indices") {
                let f = form(k);
                if !f
                    .as_ref()
                    .is_some_and(|(c, t)| [5121, 5123, 5125].contains(c) && t == "SCALAR")
                {
                    return Err(bad(
                        format!("{at}.indices"),
                        "unsigned byte, short or int SCALAR indices",
                        f,
                    ));
                }
            }
            let attrs = p.get("attributes").and_then(Value::as_object);
            for (name, k) in attrs.into_iter().flatten() {
                let Some((types, shapes)) = attribute_forms(name) else {
                    continue;
                };
                let f = form(k);
                if !f
                    .as_ref()
                    .is_some_and(|(c, t)| types.contains(c) && shapes.contains(&t.as_str()))
                {
                    let want = format!("{} with component type {types:?}", shapes.join(" or "));
                    return Err(bad(format!("{at}.attributes.{name}"), &want, f));
                }
            }
        }
    }
    check_strides(path, json)?;
    let images = json.get("images").and_then(Value::as_array);
    for (i, im) in images.into_iter().flatten().enumerate() {
        let ok = match (im.get("uri"), im.get("bufferView")) {
            (Some(_), None) => true,
            (None, Some(_)) => im.get("mimeType").is_some(),
            _ => false,
        };
        if !ok {
            return Err(err(
                path,
                format!("images[{i}]"),
                "an image needs either a uri or a bufferView with a mimeType",
            )
            .hint("re-export the model, or check it with the Khronos glTF validator"));
        }
    }
    Ok(())
}

/// Each accessor's element fits its buffer view's `byteStride` (glTF 2.0 §3.6.2.4: the stride
/// is at least the element's size): the crate asserts it (a stride of 4 on a VEC3 float
/// accessor aborted the render).
fn check_strides(path: &Path, json: &Value) -> Result<(), InputError> {
    let views = json.get("bufferViews").and_then(Value::as_array);
    let accessors = json.get("accessors").and_then(Value::as_array);
    for (i, a) in accessors.into_iter().flatten().enumerate() {
        let view = a
            .get("bufferView")
            .and_then(Value::as_u64)
            .and_then(|k| views?.get(k as usize));
        let Some(stride) = view
            .and_then(|v| v.get("byteStride"))
            .and_then(Value::as_u64)
        else {
            continue;
        };
        let size = element_size(a);
        if stride < size {
            return Err(err(
                path,
                format!("accessors[{i}]"),
                format!(
                    "its buffer view's byteStride {stride} is less than its element's {size} bytes"
                ),
            )
            .hint("re-export the model (the file breaks the specification's byteStride rule), or check it with the Khronos glTF validator"));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(doc: &str) -> Result<(), String> {
        let v: Value = serde_json::from_str(doc).unwrap();
        check_forms(Path::new("m.gltf"), &v).map_err(|e| e.to_string())
    }

    /// Accessors of a form the specification forbids, and images without a source, are named
    /// (the fuzzer's `unreachable!` and `unwrap` panics in the crate).
    #[test]
    fn accessor_forms_and_image_sources_are_checked() {
        let acc = |c: u32, t: &str| {
            format!(
                r#"{{"meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}, "indices": 1}}]}}], "accessors": [{{"componentType": 5126, "type": "VEC3", "count": 3}}, {{"componentType": {c}, "type": "{t}", "count": 3}}]}}"#
            )
        };
        check(&acc(5123, "SCALAR")).unwrap();
        let e = check(&acc(3, "SCALAR")).unwrap_err();
        assert!(
            e.contains("meshes[0].primitives[0].indices") && e.contains("componentType 3"),
            "{e}"
        );
        let e = check(&acc(5126, "SCALAR")).unwrap_err();
        assert!(e.contains("indices"), "{e}");
        let e = check(r#"{"meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}], "accessors": [{"componentType": 5123, "type": "VEC3"}]}"#).unwrap_err();
        assert!(e.contains("attributes.POSITION"), "{e}");
        check(r#"{"images": [{"uri": "a.png"}, {"bufferView": 0, "mimeType": "image/png"}]}"#)
            .unwrap();
        for doc in [
            r#"{"images": [{"name": "x"}]}"#,
            r#"{"images": [{"bufferView": 0}]}"#,
        ] {
            let e = check(doc).unwrap_err();
            assert!(e.contains("images[0]"), "{e}");
        }
    }
}
