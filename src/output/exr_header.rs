//! Sorts the attributes of a written OpenEXR file's header(s) by name, in place.
//!
//! The `exr` crate keeps custom attributes in a `HashMap` and writes them in its (per-process
//! random) iteration order, so two runs wrote the same pixels into files that differed in their
//! headers. Sorting makes the bytes a function of the content: datasets checksum frames and
//! compare runs byte for byte. The header keeps its length, so the chunk offset table after it
//! stays valid. Layout (OpenEXR file layout spec): magic, version (4 bytes each), then per
//! header `name\0 type\0 size:i32le value` attributes ended by a 0 byte; multi-part files
//! (version bit 12) end their list of headers with an empty header.

use std::ops::Range;

/// Sorts `bytes`' header attributes by name; leaves anything it cannot parse unchanged.
pub fn sort_attributes(bytes: &mut [u8]) {
    if bytes.len() < 8 || bytes[..4] != [0x76, 0x2f, 0x31, 0x01] {
        return;
    }
    let multipart = bytes[5] & 0x10 != 0;
    let mut pos = 8;
    loop {
        let start = pos;
        let mut attrs: Vec<(Vec<u8>, Range<usize>)> = Vec::new();
        loop {
            match bytes.get(pos) {
                None => return,
                Some(0) => {
                    pos += 1;
                    break;
                }
                Some(_) => {}
            }
            let Some(attr) = attribute(bytes, pos) else {
                return;
            };
            let name = bytes[pos..pos + attr.1].to_vec();
            attrs.push((name, pos..attr.0));
            pos = attr.0;
        }
        if attrs.is_empty() {
            return; // the empty header that ends a multi-part file
        }
        let end = pos - 1;
        let mut sorted = attrs.clone();
        sorted.sort_by(|a, b| a.0.cmp(&b.0));
        let text: Vec<u8> = sorted
            .iter()
            .flat_map(|(_, r)| bytes[r.clone()].to_vec())
            .collect();
        bytes[start..end].copy_from_slice(&text);
        if !multipart {
            return;
        }
    }
}

/// The end of the attribute at `pos` and the length of its name, if it is well formed.
fn attribute(b: &[u8], pos: usize) -> Option<(usize, usize)> {
    let name_len = b[pos..].iter().position(|&c| c == 0)?;
    let type_at = pos + name_len + 1;
    let type_len = b.get(type_at..)?.iter().position(|&c| c == 0)?;
    let size_at = type_at + type_len + 1;
    let size = i32::from_le_bytes(b.get(size_at..size_at + 4)?.try_into().ok()?);
    let end = size_at + 4 + usize::try_from(size).ok()?;
    (end <= b.len()).then_some((end, name_len))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn attr(name: &str, value: &[u8]) -> Vec<u8> {
        let mut v = name.as_bytes().to_vec();
        v.extend(b"\0string\0");
        v.extend((value.len() as i32).to_le_bytes());
        v.extend(value);
        v
    }

    #[test]
    fn attributes_come_out_sorted_and_the_rest_untouched() {
        let head = [0x76, 0x2f, 0x31, 0x01, 2, 0, 0, 0];
        let file = |order: &[(&str, &[u8])]| {
            let mut v = head.to_vec();
            for (n, x) in order {
                v.extend(attr(n, x));
            }
            v.push(0);
            v.extend(b"offsets and chunks");
            v
        };
        let mut a = file(&[("zeta", b"1"), ("alpha", b"22"), ("mid", b"")]);
        let mut b = file(&[("mid", b""), ("zeta", b"1"), ("alpha", b"22")]);
        sort_attributes(&mut a);
        sort_attributes(&mut b);
        assert_eq!(a, b);
        assert_eq!(a, file(&[("alpha", b"22"), ("mid", b""), ("zeta", b"1")]));
        // Not an EXR, or a truncated one: unchanged.
        let mut junk = b"hello world".to_vec();
        sort_attributes(&mut junk);
        assert_eq!(junk, b"hello world");
        let mut cut = a[..20].to_vec();
        let copy = cut.clone();
        sort_attributes(&mut cut);
        assert_eq!(cut, copy);
    }
}
